//! The ladder of every program is the program: read back as IL, it
//! compiles to the same checked program (the same instructions, STL blocks,
//! subroutines), on every program of the scenarios and program files under
//! `testsuite/` and on random programs of the differential test's
//! generators.

use crate::common;

use crate::common::tools::workspace;
use ladder_front::check::compile_source;
use ladder_front::program::{CheckedProgram, Op};
use ladder_front::source::SourceFile;
use proptest::prelude::*;
use std::path::PathBuf;

/// What runs: the instructions without their spans and lines, and the
/// program's structure.
/// (label or state, first, last) of each STL block or subroutine.
type Spans = Vec<(u32, usize, usize)>;

fn shape(program: &CheckedProgram) -> (Vec<Op>, Spans, Spans, usize) {
    (
        program.instructions.iter().map(|i| i.op.clone()).collect(),
        program.stl_blocks.iter().map(|b| (b.state, b.begin, b.end)).collect(),
        program.subroutines.iter().map(|s| (s.label, s.entry, s.end)).collect(),
        program.main_end,
    )
}

/// The IL of the program's ladder, and whether it compiles to the same
/// program (the difference, if not).
fn round_trip(name: &str, text: &str) -> Result<(), String> {
    let source = SourceFile::new(name, text);
    let (Some(program), _) = compile_source(&source) else {
        return Ok(()); // not a program (reject scenarios)
    };
    let ladder = ladder_diagram::build(&program, &source);
    let il = ladder_diagram::to_il(&ladder, &program);
    let again = SourceFile::new(format!("{name} (ladder)"), il.clone());
    let (back, diagnostics) = compile_source(&again);
    let Some(back) = back else {
        let shown = ladder_front::diagnostics::render_all(&again, &diagnostics, ladder_front::diagnostics::Shown::All);
        return Err(format!("{name}: the ladder's IL does not compile:\n{shown}\n{il}"));
    };
    if shape(&back) != shape(&program) {
        let (a, b) = (shape(&program).0, shape(&back).0);
        let first = a
            .iter()
            .zip(&b)
            .position(|(x, y)| x != y)
            .unwrap_or(a.len().min(b.len()));
        return Err(format!(
            "{name}: the ladder's IL is another program (first difference at instruction {first}: {:?} became {:?})\n{il}",
            a.get(first),
            b.get(first)
        ));
    }
    Ok(())
}

/// Every program under `testsuite/`: inline programs of scenarios and
/// program files (decoded as ladderc reads them).
fn programs() -> Vec<(String, String)> {
    let mut found = Vec::new();
    let mut pending = vec![workspace().join("testsuite")];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path: PathBuf = entry.unwrap().path();
            let name = path.display().to_string();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "il" || e == "csv") {
                found.push((name, SourceFile::read(&path).unwrap().text));
            } else if path.extension().is_some_and(|e| e == "scn") {
                let text = std::fs::read_to_string(&path).unwrap();
                if let Ok(scenario) = ladder_engine::scenario::parse_scenario(&path, &text) {
                    if let ladder_engine::scenario::ProgramSource::Inline { text, .. } = scenario.program {
                        found.push((name, text));
                    }
                }
            }
        }
    }
    found
}

#[test]
fn every_testsuite_program_is_its_ladder() {
    let programs = programs();
    assert!(programs.len() > 500, "{} programs", programs.len());
    let failures: Vec<String> = programs
        .iter()
        .filter_map(|(name, text)| round_trip(name, text).err())
        .collect();
    assert!(
        failures.is_empty(),
        "{} of {}:\n{}",
        failures.len(),
        programs.len(),
        failures.join("\n\n")
    );
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn random_programs_are_their_ladders(text in common::program()) {
        prop_assert!(round_trip("random.il", &text).is_ok(), "{}", round_trip("random.il", &text).unwrap_err());
    }

    #[test]
    fn random_fx_programs_are_their_ladders(text in common::fx::fx_program()) {
        prop_assert!(round_trip("fx.il", &text).is_ok(), "{}", round_trip("fx.il", &text).unwrap_err());
    }

    #[test]
    fn random_memory_programs_are_their_ladders(text in common::memory_program()) {
        prop_assert!(round_trip("memory.il", &text).is_ok(), "{}", round_trip("memory.il", &text).unwrap_err());
    }
}

/// What is wrong with the drawing of `text`'s ladder, if anything: every
/// element in exactly one cell, no two cells on top of each other, nothing
/// outside the grid, outputs against the right rail, no wire through a
/// cell, and every cell connected to the left rail by wires and cells.
fn drawing_faults(name: &str, text: &str) -> Result<(), String> {
    use ladder_diagram::layout::{layout, Symbol, Wire};
    use std::collections::HashMap;
    let source = SourceFile::new(name, text);
    let (Some(program), _) = compile_source(&source) else {
        return Ok(());
    };
    let ladder = ladder_diagram::build(&program, &source);
    for (number, rung) in ladder.rungs.iter().enumerate() {
        let laid = layout(rung, &program);
        let fault = |what: String| Err(format!("{name}: rung {number} (line {}): {what}\n{laid:#?}", rung.line));
        let mut drawn: Vec<usize> = laid.cells.iter().map(|c| c.element.index).collect();
        let mut expected: Vec<usize> = rung.elements().iter().map(|e| e.index).collect();
        drawn.sort_unstable();
        expected.sort_unstable();
        if laid.label.is_none() && drawn != expected {
            return fault(format!("cells {drawn:?}, elements {expected:?}"));
        }
        for (i, a) in laid.cells.iter().enumerate() {
            if a.column + a.width > laid.columns || a.row >= laid.rows || a.width == 0 {
                return fault(format!("cell {i} outside the grid"));
            }
            for b in &laid.cells[i + 1..] {
                if a.row == b.row && a.column < b.column + b.width && b.column < a.column + a.width {
                    return fault(format!("cells of {} and {} overlap", a.element.index, b.element.index));
                }
            }
        }
        // Union-find over grid points (column edge, row).
        let mut parent: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
        fn find(parent: &mut HashMap<(u32, u32), (u32, u32)>, p: (u32, u32)) -> (u32, u32) {
            let mut root = p;
            while let Some(&up) = parent.get(&root) {
                if up == root {
                    break;
                }
                root = up;
            }
            parent.insert(p, root);
            root
        }
        let join = |parent: &mut HashMap<(u32, u32), (u32, u32)>, a: (u32, u32), b: (u32, u32)| {
            let (ra, rb) = (find(parent, a), find(parent, b));
            parent.insert(ra, rb);
        };
        for row in 0..laid.rows {
            join(&mut parent, (0, row), (0, 0));
        }
        for wire in &laid.wires {
            match *wire {
                Wire::Horizontal { row, from, to } => {
                    if from >= to || to > laid.columns || row >= laid.rows {
                        return fault(format!("wire {wire:?} outside the grid"));
                    }
                    for cell in &laid.cells {
                        if cell.row == row && from < cell.column + cell.width && cell.column < to {
                            return fault(format!("wire {wire:?} runs through the cell of {}", cell.element.index));
                        }
                    }
                    for column in from..to {
                        join(&mut parent, (column, row), (column + 1, row));
                    }
                }
                Wire::Vertical { column, from, to } => {
                    if from >= to || column > laid.columns || to >= laid.rows {
                        return fault(format!("wire {wire:?} outside the grid"));
                    }
                    for row in from..to {
                        join(&mut parent, (column, row), (column, row + 1));
                    }
                }
            }
        }
        for cell in &laid.cells {
            join(
                &mut parent,
                (cell.column, cell.row),
                (cell.column + cell.width, cell.row),
            );
        }
        // A wrapped rung: each outgoing mark goes on at its incoming one.
        for out in laid.connectors.iter().filter(|c| c.outgoing) {
            let back: Vec<_> = laid
                .connectors
                .iter()
                .filter(|c| !c.outgoing && c.number == out.number)
                .collect();
            if back.len() != 1 || out.column + 1 > laid.columns || back[0].row <= out.row {
                return fault(format!("connector {} has {} ends below it", out.number, back.len()));
            }
            join(&mut parent, (out.column, out.row), (back[0].column + 1, back[0].row));
        }
        if laid.columns > ladder_diagram::layout::DEFAULT_COLUMNS {
            return fault(format!("{} columns: not wrapped", laid.columns));
        }
        let rail = find(&mut parent, (0, 0));
        for cell in &laid.cells {
            if find(&mut parent, (cell.column, cell.row)) != rail {
                return fault(format!(
                    "the cell of {} is not connected to the rail",
                    cell.element.index
                ));
            }
        }
        let outputs: Vec<usize> = match &rung.body {
            ladder_diagram::Body::Logic { tail, .. } => {
                fn walk(tail: &ladder_diagram::Tail, out: &mut Vec<usize>) {
                    for item in &tail.items {
                        match item {
                            ladder_diagram::TailItem::Output(e) => out.push(e.index),
                            ladder_diagram::TailItem::Split(branches) => branches.iter().for_each(|b| walk(b, out)),
                            ladder_diagram::TailItem::Contacts(_) => {}
                        }
                    }
                }
                let mut out = Vec::new();
                walk(tail, &mut out);
                out
            }
            ladder_diagram::Body::Step { .. }
            | ladder_diagram::Body::StepEnd { .. }
            | ladder_diagram::Body::Label { .. }
            | ladder_diagram::Body::MasterControlReset { .. }
            | ladder_diagram::Body::Rail { .. } => laid.cells.iter().map(|c| c.element.index).collect(),
        };
        for cell in laid.cells.iter().filter(|c| outputs.contains(&c.element.index)) {
            if cell.column + cell.width != laid.columns {
                return fault(format!("the output {} is not at the right rail", cell.element.index));
            }
            if !matches!(cell.symbol, Symbol::Coil { .. } | Symbol::Box { .. }) {
                return fault(format!(
                    "the output {} is drawn as {:?}",
                    cell.element.index, cell.symbol
                ));
            }
        }
    }
    // The SVG is well-formed XML, and names every element once.
    let svg = ladder_diagram::svg::render(&ladder, &program);
    let mut reader = quick_xml::Reader::from_str(&svg);
    let mut named = Vec::new();
    loop {
        match reader.read_event() {
            Ok(quick_xml::events::Event::Eof) => break,
            Ok(quick_xml::events::Event::Start(tag)) => {
                if let Ok(Some(e)) = tag.try_get_attribute("data-e") {
                    named.push(String::from_utf8_lossy(&e.value).parse::<usize>().unwrap());
                }
            }
            Ok(_) => {}
            Err(error) => return Err(format!("{name}: the SVG is not XML: {error}")),
        }
    }
    let mut all: Vec<usize> = ladder
        .rungs
        .iter()
        .filter(|r| !matches!(r.body, ladder_diagram::Body::Label { .. }))
        .flat_map(|r| r.elements().into_iter().map(|e| e.index))
        .collect();
    named.sort_unstable();
    all.sort_unstable();
    if named != all {
        return Err(format!(
            "{name}: the SVG names {} elements, the ladder has {}",
            named.len(),
            all.len()
        ));
    }
    Ok(())
}

#[test]
fn every_testsuite_program_draws_soundly() {
    let failures: Vec<String> = programs()
        .iter()
        .filter_map(|(name, text)| drawing_faults(name, text).err())
        .collect();
    assert!(failures.is_empty(), "{}:\n{}", failures.len(), failures.join("\n\n"));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn random_programs_draw_soundly(text in common::program()) {
        let faults = drawing_faults("random.il", &text);
        prop_assert!(faults.is_ok(), "{}", faults.unwrap_err());
    }

    #[test]
    fn random_fx_programs_draw_soundly(text in common::fx::fx_program()) {
        let faults = drawing_faults("fx.il", &text);
        prop_assert!(faults.is_ok(), "{}", faults.unwrap_err());
    }
}

/// The drawing says what the program says: an FX-style program that closes
/// its STL blocks with the next STL draws no RET for them (fx_station has
/// one RET, at the end of its step ladder), and `OUT Sn` inside a block
/// (a transfer, as SET) is drawn as the coil it was written as.
#[test]
fn fx_step_ladders_are_drawn_as_written() {
    let path = workspace().join("testsuite/programs/fx/fx_station.il");
    let source = SourceFile::read(&path).unwrap();
    let (program, diagnostics) = compile_source(&source);
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let svg = ladder_diagram::svg::render(&ladder_diagram::build(&program, &source), &program);
    let written = source
        .text
        .lines()
        .filter(|l| l.split_whitespace().next() == Some("RET"))
        .count();
    assert_eq!(written, 1);
    assert_eq!(svg.matches(">RET<").count(), written, "one RET, as written");

    let text = "LD M8002\nSET S20\nSTL S20\nLD X0\nOUT S21\nSTL S21\nLD X1\nSET S20\nRET\n";
    let source = SourceFile::new("out_state.il", text);
    let (program, diagnostics) = compile_source(&source);
    let program = program.unwrap_or_else(|| panic!("{diagnostics:?}"));
    let ladder = ladder_diagram::build(&program, &source);
    let svg = ladder_diagram::svg::render(&ladder, &program);
    // SET is a box (`SET` and its operand); OUT S21 a coil with the name.
    assert_eq!(
        svg.matches(">SET<").count(),
        2,
        "both SET S20 stay SET, OUT S21 is no SET:\n{svg}"
    );
    assert_eq!(svg.matches(">S21<").count(), 2, "STL S21 and the coil S21:\n{svg}");
    assert_eq!(svg.matches(">RET<").count(), 1);
    // Read back as IL, the drawing is the same program.
    let back = ladder_diagram::to_il(&ladder, &program);
    assert!(back.contains("OUT S21") && back.matches("RET").count() == 1, "{back}");
}
