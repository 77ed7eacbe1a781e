//! `ladderc test`: scenario files run against every engine (docs/scenarios.md).

mod drive;
pub mod parse;
mod run;

pub use drive::{drive, Observer, ERROR_CODE, ERROR_FLAG, ERROR_LINE};
// The engines live below the scenarios; re-exported for callers of both.
pub use crate::{instantiate, Engine, EngineError, EngineKind, InProcess, ProgramRunner};
pub use parse::{parse_scenario, parse_stimulus, Directive, ParseError, ProgramSource, Scenario, Step};
pub use run::{
    collect_files, load_program, run_scenario, EngineRun, Failure, RunOptions, ScenarioOutcome, Snapshot, Waveforms,
};
