//! `ladderc verify`: properties of a program checked for every input
//! sequence (docs/verify.md). A property file names the program, the free
//! inputs, the scan time and the properties (`property.rs`, `expr.rs`); the
//! program is a transition system of whole scans of the reference
//! interpreter (`model.rs`); an explicit-state search proves a property or
//! finds the earliest scan that breaks it (`search.rs`); a violation comes
//! back as a scenario that replays it, checked on the interpreter before it
//! is reported (`witness.rs`).

pub mod coi;
pub mod expr;
pub mod model;
pub mod property;
pub mod search;
pub mod symbolic;
pub mod witness;

use ladder_engine::pipeline::Lowered;
use ladder_engine::scenario::ProgramSource;
use ladder_front::check::compile_source;
use ladder_front::diagnostics::{render_all, Diagnostic, Shown};
use ladder_front::source::SourceFile;
use model::Model;
use property::Claim;
use search::{Limits, Outcome, Searched};
use std::path::{Path, PathBuf};

/// What was established of one property.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Verdict {
    Proved,
    ViolatedAt(u32),
    ReachedAt(u32),
    Unreachable,
    Unknown(String),
}

impl Verdict {
    /// The verdict line's text after `FILE:LINE: `.
    pub fn text(&self) -> String {
        match self {
            Verdict::Proved => "proved".to_string(),
            Verdict::ViolatedAt(n) => format!("violated at scan {n}"),
            Verdict::ReachedAt(n) => format!("reached at scan {n}"),
            Verdict::Unreachable => "unreachable".to_string(),
            Verdict::Unknown(why) => format!("unknown ({why})"),
        }
    }

    /// Passed (`Some(true)`), failed (`Some(false)`) or unknown (`None`).
    pub fn passed(&self) -> Option<bool> {
        match self {
            Verdict::Proved | Verdict::ReachedAt(_) => Some(true),
            Verdict::ViolatedAt(_) | Verdict::Unreachable => Some(false),
            Verdict::Unknown(_) => None,
        }
    }
}

/// One property's result.
#[derive(Clone, Debug)]
pub struct PropertyReport {
    pub line: u32,
    pub verdict: Verdict,
    /// Vacuity and unused devices.
    pub warnings: Vec<String>,
    /// The witness scenario of a violation or a reached condition.
    pub witness: Option<String>,
    pub searched: Searched,
}

/// Why a property file was not checked (exit status 2).
#[derive(Debug)]
pub enum FileError {
    /// It cannot be read.
    Read(String),
    /// Diagnostics, rendered with file:line:col and the text underlined.
    Invalid(String),
}

/// How `verify_file` works.
#[derive(Clone, Debug, Default)]
pub struct Options {
    pub limits: Limits,
    pub engine: Engine,
}

/// Which engines decide a property.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Engine {
    /// The explicit-state search, then (when it cannot answer) the
    /// SAT-based engines.
    #[default]
    Auto,
    /// The explicit-state search alone.
    Explicit,
    /// The SAT-based engines alone (BMC, k-induction, IC3).
    Symbolic,
}

/// The witness file of a property: `DIR/NAME-LINE.scn`.
pub fn witness_path(dir: &Path, file: &Path, line: u32) -> PathBuf {
    let stem = file.file_stem().map_or("properties".into(), |s| s.to_string_lossy());
    dir.join(format!("{stem}-{line}.scn"))
}

/// Checks every property of the file at `path`.
pub fn verify_file(path: &Path, options: &Options) -> Result<Vec<PropertyReport>, FileError> {
    let source = SourceFile::read(path).map_err(|e| FileError::Read(format!("{}: {e}", path.display())))?;
    verify_source(path, &source, options)
}

/// Checks every property of a property file's text; `path` names it (and
/// a `program FILE` is found beside it).
/// A property file read and its program compiled.
struct Loaded {
    file: property::PropertyFile,
    program_source: SourceFile,
    checked: ladder_front::program::CheckedProgram,
}

/// Parses a property file's text and compiles its program.
fn load(path: &Path, source: &SourceFile) -> Result<Loaded, FileError> {
    let source = source.clone();
    let file = property::parse_file(path, &source).map_err(|d| FileError::Invalid(render(&source, &d)))?;
    let program_source = match &file.program {
        ProgramSource::File(program) => {
            SourceFile::read(program).map_err(|e| FileError::Read(format!("{}: {e}", program.display())))?
        }
        ProgramSource::Inline { text, .. } => SourceFile::new(format!("{} (program)", path.display()), text.clone()),
    };
    let (checked, diagnostics) = compile_source(&program_source);
    let Some(checked) = checked else {
        // An inline program's lines are counted from its block: each
        // diagnostic also says where it is in the property file.
        let located: Vec<Diagnostic> = match &file.program {
            ProgramSource::Inline { first_line, .. } => diagnostics
                .iter()
                .cloned()
                .map(|d| {
                    let line = first_line + program_source.line_of(d.span.start) - 1;
                    d.with_note(format!("line {line} of {}", path.display()))
                })
                .collect(),
            ProgramSource::File(_) => diagnostics.to_vec(),
        };
        return Err(FileError::Invalid(render_all(
            &program_source,
            &located,
            Shown::default(),
        )));
    };
    Ok(Loaded {
        file,
        program_source,
        checked,
    })
}

pub fn verify_source(path: &Path, source: &SourceFile, options: &Options) -> Result<Vec<PropertyReport>, FileError> {
    let Loaded {
        file,
        program_source,
        checked,
    } = load(path, source)?;
    let lowered = Lowered::new(&checked);
    let mut reports = Vec::new();
    for property in &file.properties {
        // A model per property: its cone, and only the inputs in it.
        let model =
            Model::new(&checked, lowered.ir(), &file, Some(&property.claim)).map_err(|e| FileError::Invalid(e.0))?;
        let decided = decide(&model, lowered.ir(), &file, &property.claim, options);
        let searched = decided.searched;
        let mut warnings = unused_devices(&model, &property.claim);
        if !decided.unmodelled.is_empty() {
            warnings.push(format!(
                "the SAT-based engines took these as arbitrary: {}",
                decided.unmodelled.join("; ")
            ));
        }
        let mut witness = None;
        let verdict = match (&property.claim, decided.outcome) {
            (Claim::Never(_) | Claim::Always(_) | Claim::Respond { .. }, Outcome::Exhausted) => Verdict::Proved,
            (Claim::Reach(_), Outcome::Exhausted) => Verdict::Unreachable,
            (claim, Outcome::Found { path: choices }) => {
                let scan = choices.len() as u32;
                let verdict = match claim {
                    Claim::Reach(_) => Verdict::ReachedAt(scan),
                    Claim::Never(_) | Claim::Always(_) | Claim::Respond { .. } => Verdict::ViolatedAt(scan),
                };
                let title = format!("{}:{}: {}", path.display(), property.line, verdict.text());
                let scenario_path = witness_path(Path::new("."), path, property.line);
                let replayed = witness::scenario(&model, &file, &program_source.text, claim, &title, &choices)
                    .and_then(|text| witness::replay(&scenario_path, &text).map(|()| text));
                match replayed {
                    Ok(text) => {
                        witness = Some(text);
                        verdict
                    }
                    // A model that took something as arbitrary may find a
                    // counterexample the program cannot follow.
                    Err(why) if !decided.unmodelled.is_empty() => Verdict::Unknown(format!(
                        "a counterexample needs {}, and it does not replay ({why})",
                        decided.unmodelled.join("; ")
                    )),
                    Err(why) => Verdict::Unknown(format!("a bug of the verifier: its witness does not replay ({why})")),
                }
            }
            (_, Outcome::Unknown(why)) => Verdict::Unknown(why),
        };
        if matches!(verdict, Verdict::Proved | Verdict::Unreachable) && searched.transitions == 0 {
            warnings.push("vacuous: the assumptions rule out every input of the first scan".to_string());
        } else if verdict == Verdict::Proved && !searched.condition_seen {
            let condition = match &property.claim {
                Claim::Always(expr::Expr::Implies(..)) => Some("its condition (left of `->`)"),
                Claim::Respond { .. } => Some("its trigger"),
                Claim::Always(_) | Claim::Never(_) | Claim::Reach(_) => None,
            };
            if let Some(condition) = condition {
                warnings.push(format!(
                    "vacuous: {condition} is never true, so the property holds without saying anything"
                ));
            }
        }
        reports.push(PropertyReport {
            line: property.line,
            verdict,
            warnings,
            witness,
            searched,
        });
    }
    Ok(reports)
}

/// The property at `line` of the file at `path` as a binary AIGER model
/// (`ladderc verify --emit aiger`): its output is ON after a scan that
/// breaks the property (for `reach`: that shows its condition). With it,
/// what the model takes as arbitrary values (a model checker's
/// counterexample may need them; its proof stays a proof).
pub fn emit_aiger(path: &Path, line: u32) -> Result<(Vec<u8>, Vec<String>), FileError> {
    let source = SourceFile::read(path).map_err(|e| FileError::Read(format!("{}: {e}", path.display())))?;
    let Loaded { file, checked, .. } = load(path, &source)?;
    let Some(property) = file.properties.iter().find(|p| p.line == line) else {
        let lines: Vec<String> = file.properties.iter().map(|p| p.line.to_string()).collect();
        return Err(FileError::Read(format!(
            "{}: no property on line {line} (properties are on lines {})",
            path.display(),
            lines.join(", ")
        )));
    };
    let lowered = Lowered::new(&checked);
    let model =
        Model::new(&checked, lowered.ir(), &file, Some(&property.claim)).map_err(|e| FileError::Invalid(e.0))?;
    let system = symbolic::system::build(&model, lowered.ir(), &file, &property.claim).map_err(|e| {
        FileError::Read(format!(
            "{}:{line}: the property cannot be written as AIGER: {}",
            path.display(),
            e.0
        ))
    })?;
    let nodes = &system.aig.nodes;
    let names: Vec<(u32, String)> = model
        .inputs
        .iter()
        .zip(&system.inputs)
        .flat_map(|(input, bits)| {
            let (device, width) = model::input_device(*input);
            let name = witness::name(ladder_front::host_device::HostDevice { device, width }).0;
            let several = bits.len() > 1;
            bits.iter().enumerate().filter_map(move |(i, bit)| {
                let number = match nodes.get(bit.node() as usize) {
                    Some(symbolic::aig::Node::Input(n)) => *n,
                    _ => return None,
                };
                Some((number, if several { format!("{name}[{i}]") } else { name.clone() }))
            })
        })
        .collect();
    Ok((symbolic::aiger::write(&system, &names), system.unmodelled.clone()))
}

/// What the engines found of one property.
struct Decided {
    outcome: Outcome,
    searched: Searched,
    /// What the SAT-based engines took as arbitrary, when they answered.
    unmodelled: Vec<String>,
}

/// Decides a property: the explicit-state search first (exact, and the
/// shortest counterexample), then, when it cannot answer, the SAT-based
/// engines with the time left.
fn decide(
    model: &Model,
    ir: &ladder_ir::Program,
    file: &property::PropertyFile,
    claim: &Claim,
    options: &Options,
) -> Decided {
    let start = std::time::Instant::now();
    let mut explicit_reason = None;
    if options.engine != Engine::Symbolic {
        let mut limits = options.limits;
        if options.engine == Engine::Auto {
            // Half the time, so the SAT-based engines get the rest.
            limits.timeout /= 2;
        }
        let (outcome, searched) = search::search(model, claim, &limits);
        match outcome {
            Outcome::Unknown(why) if options.engine == Engine::Auto => explicit_reason = Some(why),
            Outcome::Exhausted | Outcome::Found { .. } | Outcome::Unknown(_) => {
                return Decided {
                    outcome,
                    searched,
                    unmodelled: Vec::new(),
                }
            }
        }
    }
    let deadline = start + options.limits.timeout;
    let unknown = |why: String| Decided {
        outcome: Outcome::Unknown(why),
        searched: Searched::default(),
        unmodelled: Vec::new(),
    };
    let system = match symbolic::system::build(model, ir, file, claim) {
        Ok(system) => system,
        Err(symbolic::encode::Unsupported(why)) => {
            return unknown(match explicit_reason {
                Some(explicit) => format!("{explicit}; the SAT-based engines cannot take it: {why}"),
                None => format!("the SAT-based engines cannot take it: {why}"),
            })
        }
    };
    let decision = symbolic::check(&system, options.limits.depth, deadline);
    let answer = decision.answer;
    let mut searched = Searched {
        transitions: 1,
        by_sat: Some(decision.by),
        ..Searched::default()
    };
    let outcome = match answer {
        symbolic::bmc::Answer::Holds => {
            // Vacuity: can the first scan's inputs meet the assumptions?
            let first = symbolic::System {
                bad: system.valid,
                ..system.clone()
            };
            let mut bmc = symbolic::bmc::Bmc::new(&first, deadline);
            if let Some(symbolic::bmc::Answer::Holds) | None = bmc.step(1, false) {
                searched.transitions = 0;
            }
            // Vacuity: can the condition be true at all?
            if let Some(condition) = system.condition {
                let question = symbolic::System {
                    bad: condition,
                    ..system.clone()
                };
                let seen = symbolic::check(&question, options.limits.depth, deadline);
                searched.condition_seen = !matches!(seen.answer, symbolic::bmc::Answer::Holds);
            }
            Outcome::Exhausted
        }
        symbolic::bmc::Answer::Fails(frames) => {
            searched.depth = frames.len() as u32;
            Outcome::Found {
                path: symbolic::choices(model, &frames),
            }
        }
        symbolic::bmc::Answer::Unknown(why) => Outcome::Unknown(match explicit_reason {
            // Both stopped at the same limit: said once.
            Some(explicit) if explicit == why => why,
            Some(explicit) => format!("{explicit}; the SAT-based engines: {why}"),
            None => why,
        }),
    };
    Decided {
        outcome,
        searched,
        unmodelled: system.unmodelled,
    }
}

fn render(source: &SourceFile, diagnostics: &[Diagnostic]) -> String {
    render_all(source, diagnostics, Shown::default())
}

/// A warning for each device the property names that the program neither
/// reads nor writes (and that is not a free input).
fn unused_devices(model: &Model, claim: &Claim) -> Vec<String> {
    let mut named = Vec::new();
    for e in claim.exprs() {
        e.devices(&mut named);
    }
    let mut warnings = Vec::new();
    let mut said = Vec::new();
    for (device, _) in named {
        if said.contains(&device) || model.program_uses(device) {
            continue;
        }
        said.push(device);
        let is_input = model.inputs.iter().any(|&input| {
            let (d, _) = model::input_device(input);
            d == device.device
        });
        if !is_input {
            warnings.push(format!(
                "{} is neither read nor written by the program",
                witness::name(device).0
            ));
        }
    }
    warnings
}

/// The property files under `path`: the file itself, or every `*.prop` in
/// a folder, recursively, sorted.
pub fn collect_files(path: &Path) -> std::io::Result<Vec<PathBuf>> {
    if !path.is_dir() {
        return Ok(vec![path.to_path_buf()]);
    }
    let mut files = Vec::new();
    let mut folders = vec![path.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder)? {
            let entry = entry?;
            // Not through links to folders: a link to a parent would loop.
            let kind = entry.file_type()?;
            let entry = entry.path();
            if kind.is_dir() {
                folders.push(entry);
            } else if entry.extension().is_some_and(|e| e == "prop") {
                files.push(entry);
            }
        }
    }
    files.sort();
    Ok(files)
}

#[cfg(test)]
mod tests;
