//! `ladderc test`: scenario files run against every engine (SCENARIO.md).

mod engine;
mod parse;
mod run;

pub use engine::{instantiate, Engine, EngineError, EngineKind, InProcess, ProgramRunner};
pub use parse::{parse_scenario, Directive, ParseError, ProgramSource, Scenario, Step};
pub use run::{collect_files, load_program, run_scenario, Failure, ScenarioOutcome};
