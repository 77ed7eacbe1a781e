//! `ladderc test`: scenario files run against every engine (SCENARIO.md).

mod drive;
mod engine;
mod parse;
mod run;

pub use drive::{drive, Observer, ERROR_CODE, ERROR_FLAG, ERROR_LINE};
pub use engine::{instantiate, Engine, EngineError, EngineKind, InProcess, ProgramRunner};
pub use parse::{parse_scenario, parse_stimulus, Directive, ParseError, ProgramSource, Scenario, Step};
pub use run::{
    collect_files, load_program, run_scenario, EngineRun, Failure, RunOptions, ScenarioOutcome, Snapshot, Waveforms,
};
