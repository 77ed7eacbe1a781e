//! `ladderc test`: scenario files, as the scenario format describes. Files
//! run on every core; the report comes out in file order whatever finished
//! first, with a progress bar on a terminal for long suites.

use super::{output, status};
use clap::Args;
use ladder_engine::scenario::{
    collect_files, parse_scenario, run_scenario, EngineKind, RunOptions, Scenario, ScenarioOutcome, Waveforms,
};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

#[derive(Args, Debug, Default)]
pub struct TestArgs {
    /// Scenario files, or folders searched for `*.scn` (recursively).
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    /// Engines to run each scenario on.
    #[arg(long, value_enum, default_value_t = super::EngineChoice::All)]
    pub engine: super::EngineChoice,
    /// Write a JUnit XML report (a testsuite per file, a testcase per
    /// scenario and engine) for CI systems.
    #[arg(long, value_name = "OUT.xml")]
    pub junit: Option<PathBuf>,
    /// Write a VCD waveform per failing scenario and engine into this folder
    /// (`NAME.ENGINE.vcd`): the devices the scenario sets, forces, expects
    /// or prints, and the program's coils.
    #[arg(long, value_name = "DIR")]
    pub vcd: Option<PathBuf>,
    /// With --vcd: a waveform for every scenario, passed ones too.
    #[arg(long, requires = "vcd")]
    pub vcd_all: bool,
    /// Write a page per failing scenario and engine into this folder
    /// (`NAME.ENGINE.html`): the ladder at each failed expectation, with the
    /// values the engine left, and the waveform of the devices it touches.
    #[arg(long, value_name = "DIR")]
    pub html: Option<PathBuf>,
    /// Show what `print` directives print.
    #[arg(short, long)]
    pub verbose: bool,
    /// Run shard K of N (`--shard 2/4`): every Nth scenario file of the
    /// sorted list, starting with the Kth, so N machines (a CI matrix, a
    /// job array) given the same paths share a suite between them, each
    /// file on exactly one.
    #[arg(long, value_name = "K/N", value_parser = parse_shard)]
    pub shard: Option<Shard>,
}

/// One share of a suite: shard `index` (1-based) of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

/// `K/N` with 1 <= K <= N.
pub fn parse_shard(text: &str) -> Result<Shard, String> {
    let wrong = || format!("`{text}` is not a shard like 2/4 (shard K of N, 1 <= K <= N)");
    let (index, count) = text.split_once('/').ok_or_else(wrong)?;
    let index: usize = index.trim().parse().map_err(|_| wrong())?;
    let count: usize = count.trim().parse().map_err(|_| wrong())?;
    if index == 0 || index > count {
        return Err(wrong());
    }
    Ok(Shard { index, count })
}

/// The files of `shard`: sorted by path, every `count`th from the
/// `index`th, so the shares are equal in number and the same on every
/// machine that names the same paths.
pub fn shard_files(mut files: Vec<PathBuf>, shard: Shard) -> Vec<PathBuf> {
    files.sort();
    files
        .into_iter()
        .enumerate()
        .filter(|(n, _)| n % shard.count == shard.index - 1)
        .map(|(_, file)| file)
        .collect()
}

/// One scenario file's result.
struct FileResult {
    path: PathBuf,
    /// None: the file or its program could not be read (already reported).
    outcome: Option<ScenarioOutcome>,
    /// Errors reading or parsing, to print in order.
    errors: Vec<String>,
}

pub fn run(args: &TestArgs) -> u8 {
    run_with(&mut std::io::stdout().lock(), args, &args.engine.kinds())
}

/// `ladderc test PATHS` on `engines`, writing its report to `out`.
pub fn run_to(out: &mut dyn Write, paths: &[PathBuf], engines: &[EngineKind]) -> u8 {
    let args = TestArgs {
        paths: paths.to_vec(),
        ..TestArgs::default()
    };
    run_with(out, &args, engines)
}

/// `ladderc test` writing its report to `out` (failures, details, engine
/// lines, and the summary line last). Errors reading files go to stderr.
pub fn run_with(out: &mut dyn Write, args: &TestArgs, engines: &[EngineKind]) -> u8 {
    let engines = engines.to_vec();
    let mut unusable = false;
    let mut files = Vec::new();
    for path in &args.paths {
        match collect_files(path) {
            Ok(found) => files.extend(found),
            Err(error) => {
                say_err!("error: cannot read {}: {error}", path.display());
                unusable = true;
            }
        }
    }
    // A file named twice (or found through two folders) runs once.
    let mut seen = std::collections::HashSet::new();
    files.retain(|file| seen.insert(file.canonicalize().unwrap_or_else(|_| file.clone())));
    if files.is_empty() && !unusable {
        let shown: Vec<String> = args.paths.iter().map(|p| p.display().to_string()).collect();
        say_err!("error: no scenario files (*.scn) in {}", shown.join(", "));
        return status::UNUSABLE;
    }
    if let Some(shard) = args.shard {
        let all = files.len();
        files = shard_files(files, shard);
        let _ = writeln!(
            out,
            "shard {}/{}: {} of {all} scenario files",
            shard.index,
            shard.count,
            files.len()
        );
    }
    for dir in [&args.vcd, &args.html].into_iter().flatten() {
        if let Err(error) = std::fs::create_dir_all(dir) {
            say_err!("error: cannot create {}: {error}", dir.display());
            return status::UNUSABLE;
        }
    }
    let options = RunOptions {
        waveforms: match (&args.vcd, args.vcd_all, &args.html) {
            (None, _, None) => Waveforms::None,
            (Some(_), true, _) => Waveforms::All,
            (Some(_), false, _) | (None, _, Some(_)) => Waveforms::Failing,
        },
        snapshots: args.html.is_some(),
    };
    // Outputs must not be any scenario or program file: checked before the
    // run, so a refused output costs no time and destroys nothing.
    let programs: Vec<PathBuf> = files.iter().filter_map(|file| program_file(file)).collect();
    let inputs: Vec<&Path> = files.iter().chain(&programs).map(PathBuf::as_path).collect();
    if let Some(path) = &args.junit {
        if let Err(error) = output::prepare(path, &inputs) {
            say_err!("error: {error}");
            return status::UNUSABLE;
        }
    }
    let results = run_all(&files, &engines, options);
    let (mut passed, mut failed) = (0usize, 0usize);
    let mut ran: BTreeMap<EngineKind, usize> = BTreeMap::new();
    let mut skipped: BTreeMap<EngineKind, String> = BTreeMap::new();
    for result in &results {
        for error in &result.errors {
            say_err!("{error}");
        }
        let Some(outcome) = &result.outcome else {
            unusable = true;
            continue;
        };
        for failure in &outcome.failures {
            let _ = writeln!(out, "{failure}");
        }
        let _ = out.write_all(outcome.details.as_bytes());
        if args.verbose {
            for engine in &outcome.engines {
                for line in &engine.printed {
                    let _ = writeln!(out, "{}: {line}", result.path.display());
                }
            }
        }
        for kind in &outcome.ran {
            *ran.entry(*kind).or_default() += 1;
        }
        for (kind, reason) in &outcome.skipped {
            skipped.entry(*kind).or_insert_with(|| reason.clone());
        }
        // A scenario no engine could run is neither passed nor failed; the
        // skip lines say why.
        let ran_nothing = outcome.ran.is_empty() && !outcome.skipped.is_empty();
        if !outcome.failures.is_empty() {
            failed += 1;
        } else if !ran_nothing {
            passed += 1;
        }
    }
    if let Some(dir) = &args.vcd {
        if let Err(error) = write_waveforms(dir, &results, &inputs) {
            say_err!("error: {error}");
            unusable = true;
        }
    }
    if let Some(dir) = &args.html {
        if let Err(error) = write_pages(dir, &results, &inputs) {
            say_err!("error: {error}");
            unusable = true;
        }
    }
    if let Some(path) = &args.junit {
        if let Err(error) = super::report::write_junit(path, &results_for_report(&results), &inputs) {
            say_err!("error: {error}");
            unusable = true;
        }
    }
    let ran_names: Vec<&str> = ran.keys().map(|k| k.name()).collect();
    let engines_line = if ran_names.is_empty() {
        "none".to_string()
    } else {
        ran_names.join(", ")
    };
    let _ = writeln!(out, "engines: {engines_line}");
    for (kind, reason) in &skipped {
        let _ = writeln!(out, "skipped {}: {reason}", kind.name());
    }
    let _ = writeln!(out, "{passed} passed, {failed} failed");
    if ran.is_empty() && !skipped.is_empty() {
        // Nothing ran at all (say `--engine aot` without a C compiler): not
        // a pass.
        say_err!("error: no engine could run the scenarios");
        return status::UNUSABLE;
    }
    if unusable {
        status::UNUSABLE
    } else if failed > 0 {
        status::FAILED
    } else {
        status::OK
    }
}

fn results_for_report(results: &[FileResult]) -> Vec<super::report::FileReport<'_>> {
    results
        .iter()
        .map(|r| super::report::FileReport {
            path: &r.path,
            outcome: r.outcome.as_ref(),
            errors: &r.errors,
        })
        .collect()
}

/// The program file a scenario names, if it names one and can be read.
fn program_file(scenario: &Path) -> Option<PathBuf> {
    let bytes = ladder_front::source::read_bounded(scenario).ok()?;
    let parsed = parse_scenario(scenario, &String::from_utf8_lossy(&bytes)).ok()?;
    match parsed.program {
        ladder_engine::scenario::ProgramSource::File(path) => Some(path),
        ladder_engine::scenario::ProgramSource::Inline { .. } => None,
    }
}

/// Runs every file on a pool of threads (one per core); results in file
/// order.
fn run_all(files: &[PathBuf], engines: &[EngineKind], options: RunOptions) -> Vec<FileResult> {
    let workers = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(files.len())
        .max(1);
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<FileResult>>> = Mutex::new((0..files.len()).map(|_| None).collect());
    let progress = indicatif::ProgressBar::new(files.len() as u64);
    // Drawn on a terminal only, and only for suites long enough to wait for.
    if files.len() < 20 {
        progress.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| loop {
                let index = next.fetch_add(1, Ordering::Relaxed);
                let Some(file) = files.get(index) else {
                    break;
                };
                let result = run_file(file, engines, options);
                if let Ok(mut results) = results.lock() {
                    results[index] = Some(result);
                }
                progress.inc(1);
            });
        }
    });
    progress.finish_and_clear();
    results
        .into_inner()
        .unwrap_or_default()
        .into_iter()
        .zip(files)
        .map(|(result, path)| {
            result.unwrap_or_else(|| FileResult {
                path: path.clone(),
                outcome: None,
                errors: vec![format!("error: {}: the run did not finish", path.display())],
            })
        })
        .collect()
}

fn run_file(file: &Path, engines: &[EngineKind], options: RunOptions) -> FileResult {
    let mut result = FileResult {
        path: file.to_path_buf(),
        outcome: None,
        errors: Vec::new(),
    };
    match load(file) {
        Ok((scenario, source)) => result.outcome = Some(run_scenario(&scenario, &source, engines, options)),
        Err(error) => result.errors.push(error),
    }
    result
}

/// Reads and parses a scenario and its program.
fn load(file: &Path) -> Result<(Scenario, ladder_front::source::SourceFile), String> {
    let bytes = ladder_front::source::read_bounded(file).map_err(|error| format!("error: {error}"))?;
    let text = String::from_utf8_lossy(&bytes).into_owned();
    let scenario = parse_scenario(file, &text).map_err(|error| {
        let hint = match file.extension().and_then(|e| e.to_str()) {
            Some("scn") | None => String::new(),
            Some(_) => " (is this a program? `ladderc test` takes scenario files, *.scn)".to_string(),
        };
        format!("{}:{}: error: {}{hint}", file.display(), error.line, error.message)
    })?;
    let source = ladder_engine::scenario::load_program(&scenario)
        .map_err(|message| format!("{}: error: {message}", file.display()))?;
    Ok((scenario, source))
}

/// The file stem for a scenario's outputs: its path with `__` for folder
/// separators.
fn stem_of(path: &Path) -> String {
    path.with_extension("")
        .to_string_lossy()
        .replace(['/', '\\'], "__")
        .trim_start_matches(['_', '.'])
        .to_string()
}

/// `base`, or `base-2`, `base-3`, ... when taken.
fn unique(taken: &mut std::collections::HashSet<String>, base: String) -> String {
    (1..)
        .map(|n| if n == 1 { base.clone() } else { format!("{base}-{n}") })
        .find(|name| taken.insert(name.clone()))
        .unwrap_or(base)
}

/// `DIR/NAME.ENGINE.html` for every engine run with a failed expectation.
fn write_pages(dir: &Path, results: &[FileResult], inputs: &[&Path]) -> Result<(), String> {
    let mut taken = std::collections::HashSet::new();
    for result in results {
        let Some(outcome) = &result.outcome else { continue };
        let failing: Vec<&ladder_engine::scenario::EngineRun> = outcome
            .engines
            .iter()
            .filter(|run| outcome.failures.iter().any(|f| f.engine == run.kind.name()))
            .collect();
        if failing.is_empty() {
            continue;
        }
        // The program again (it compiled for the run).
        let Ok((_, source)) = load(&result.path) else { continue };
        let (Some(program), _) = ladder_front::check::compile_source(&source) else {
            continue;
        };
        for run in failing {
            let name = unique(&mut taken, format!("{}.{}", stem_of(&result.path), run.kind.name()));
            let path = dir.join(format!("{name}.html"));
            let page = super::html_report::page(&result.path.display().to_string(), run, &program, &source);
            let target = output::prepare(&path, inputs).map_err(|e| e.to_string())?;
            output::write_atomically(&target, page.as_bytes())
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
    }
    Ok(())
}

/// `DIR/NAME.ENGINE.vcd` for every kept waveform, NAME the scenario's path
/// (`__` for its folder separators); a name taken twice gets `-2`, `-3`.
fn write_waveforms(dir: &Path, results: &[FileResult], inputs: &[&Path]) -> Result<(), String> {
    let mut taken = std::collections::HashSet::new();
    for result in results {
        let Some(outcome) = &result.outcome else { continue };
        let stem = stem_of(&result.path);
        for engine in &outcome.engines {
            let Some(waveform) = &engine.waveform else { continue };
            let name = unique(&mut taken, format!("{stem}.{}", engine.kind.name()));
            let path = dir.join(format!("{name}.vcd"));
            let bytes = waveform
                .to_vcd()
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
            let target = output::prepare(&path, inputs).map_err(|e| e.to_string())?;
            output::write_atomically(&target, &bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        }
    }
    Ok(())
}
