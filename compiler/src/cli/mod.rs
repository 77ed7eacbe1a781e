//! The `ladderc` command line. Every command returns its exit status; nothing
//! here exits the process.

/// `println!` that never panics: a closed stdout (`ladderc test | head`) is
/// not an error of ours.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($arg)*);
    }};
}

/// `eprintln!` that never panics.
macro_rules! say_err {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr().lock(), $($arg)*);
    }};
}

/// Writes text as is (already ending in a newline) without panicking.
fn write_raw(to_stderr: bool, text: &str) {
    use std::io::Write as _;
    let _ = if to_stderr {
        std::io::stderr().lock().write_all(text.as_bytes())
    } else {
        std::io::stdout().lock().write_all(text.as_bytes())
    };
}

mod build;
mod check;
mod explain;
mod fmu;
mod html_report;
mod import;
mod output;
mod render;
mod report;
mod run;
mod serve;
pub mod test;
mod verify;

use clap::{Parser, Subcommand, ValueEnum};
use ladder_engine::scenario::EngineKind;
use ladder_front::diagnostics::Shown;
use std::path::PathBuf;

/// Exit statuses shared by the commands.
pub mod status {
    pub const OK: u8 = 0;
    /// The program has errors, or a test failed.
    pub const FAILED: u8 = 1;
    /// A file could not be read or parsed, or the arguments are wrong.
    pub const UNUSABLE: u8 = 2;
}

#[derive(Parser, Debug)]
#[command(
    name = "ladderc",
    version,
    about = "Compiler for Mitsubishi-FX/Wecon-style PLC instruction lists"
)]
pub struct Cli {
    /// Print every diagnostic (by default, after 20 warnings or 200 errors
    /// of one code the rest are counted: "and 17,412 more W0002 warnings").
    #[arg(long, global = true)]
    pub all_diagnostics: bool,
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Check a program and print its diagnostics.
    Check {
        /// The program: IL or a GX Works2 CSV export (`-` reads standard input).
        program: PathBuf,
    },
    /// Compile a program to an object file (or show its IR).
    Build(build::BuildArgs),
    /// Run a program for some scans and print watched devices after each.
    Run(run::RunArgs),
    /// Draw the program as a ladder diagram (SVG, or an HTML page).
    Render(render::RenderArgs),
    /// Run scenario files (folders are searched for *.scn).
    Test(test::TestArgs),
    /// Prove properties of a program for every input sequence, or find a
    /// sequence that breaks them (property files; folders are searched for
    /// *.prop).
    Verify(verify::VerifyArgs),
    /// Explain a diagnostic code such as E0010 (without one: list every code).
    Explain {
        /// A code such as E0010 or W0002.
        code: Option<String>,
    },
    /// Run the program as a soft PLC: scans in real time, serves Modbus TCP.
    Serve(Box<serve::ServeArgs>),
    /// Print a shell completion script: `ladderc completions bash > /etc/bash_completion.d/ladderc`.
    Completions {
        /// The shell.
        shell: clap_complete::Shell,
    },
    /// Convert a GX Works2 instruction-list CSV export or a GX Developer
    /// project to plain IL (step numbers kept, line statements and notes as
    /// comments, a project's device comments and parameters as `//@`
    /// lines). The IL compiles to the same program. With
    /// --to-gx-developer, write a program as a GX Developer project instead.
    Import {
        /// The CSV export (UTF-16 or UTF-8), the GX Developer project (its
        /// folder, .gps file or MAIN.wpg), or with --to-gx-developer any
        /// program.
        export: PathBuf,
        /// Where to write the IL (default: standard output).
        #[arg(short, long, conflicts_with = "to_gx_developer")]
        output: Option<PathBuf>,
        /// Write the program as Pou/Body/MAIN.wpg and Others/COMMENT.wcd of
        /// the GX Developer project in this folder (its other files are
        /// kept; the folder is made if it is missing).
        #[arg(long, value_name = "DIR")]
        to_gx_developer: Option<PathBuf>,
    },
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum EngineChoice {
    Interp,
    Jit,
    Aot,
    C,
    /// The C route with a compact image (the devices the program and the
    /// scenario use).
    #[value(name = "c-compact")]
    CCompact,
    #[default]
    All,
}

impl EngineChoice {
    pub fn kinds(self) -> Vec<EngineKind> {
        match self {
            EngineChoice::Interp => vec![EngineKind::Interp],
            EngineChoice::Jit => vec![EngineKind::Jit],
            EngineChoice::Aot => vec![EngineKind::Aot],
            EngineChoice::C => vec![EngineKind::C],
            EngineChoice::CCompact => vec![EngineKind::CCompact],
            EngineChoice::All => EngineKind::ALL.to_vec(),
        }
    }
}

/// Runs the command line `args` (including the program name).
pub fn main_with_args(args: impl IntoIterator<Item = std::ffi::OsString>) -> u8 {
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(error) => {
            write_raw(error.use_stderr(), &error.render().to_string());
            return if error.use_stderr() {
                status::UNUSABLE
            } else {
                status::OK
            };
        }
    };
    let shown = if cli.all_diagnostics {
        Shown::All
    } else {
        Shown::default()
    };
    match cli.command {
        Command::Check { program } => check::run(&program, shown),
        Command::Build(args) => build::run(&args, shown),
        Command::Run(args) => run::run(&args, shown),
        Command::Test(args) => test::run(&args),
        Command::Verify(args) => verify::run(&args),
        Command::Render(args) => render::run(&args, shown),
        Command::Explain { code } => explain::run(code.as_deref()),
        Command::Completions { shell } => {
            use clap::CommandFactory as _;
            let mut command = Cli::command();
            clap_complete::generate(shell, &mut command, "ladderc", &mut std::io::stdout());
            status::OK
        }
        Command::Serve(args) => serve::run(&args, shown),
        Command::Import {
            export,
            output,
            to_gx_developer,
        } => match to_gx_developer {
            Some(dir) => import::to_gx_developer(&export, &dir, shown),
            None => import::run(&export, output.as_ref(), shown),
        },
    }
}

/// Reads and compiles a program file, printing diagnostics to stderr.
/// `Err` holds the exit status to return.
fn compile_file(path: &std::path::Path, shown: Shown) -> Result<ladder_front::program::CheckedProgram, u8> {
    compile_file_with_source(path, shown).map(|(program, _)| program)
}

/// `compile_file`, with the source it read (for its comments).
fn compile_file_with_source(
    path: &std::path::Path,
    shown: Shown,
) -> Result<(ladder_front::program::CheckedProgram, ladder_front::source::SourceFile), u8> {
    let source = read_program(path).map_err(|e| {
        say_err!("error: {e}");
        status::UNUSABLE
    })?;
    let (program, diagnostics) = ladder_front::check::compile_source(&source);
    write_raw(
        true,
        &ladder_front::diagnostics::render_all(&source, &diagnostics, shown),
    );
    program.map(|program| (program, source)).ok_or(status::FAILED)
}

/// `-` for standard input or output.
fn is_standard_stream(path: &std::path::Path) -> bool {
    path.as_os_str() == "-"
}

/// A program file, or standard input for `-` (at most the same 64 MiB).
fn read_program(path: &std::path::Path) -> Result<ladder_front::source::SourceFile, String> {
    use std::io::Read as _;
    if !is_standard_stream(path) {
        return ladder_front::source::SourceFile::read(path).map_err(|e| e.to_string());
    }
    let mut bytes = Vec::new();
    std::io::stdin()
        .lock()
        .take(ladder_front::source::MAX_SOURCE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read standard input: {e}"))?;
    if bytes.len() as u64 > ladder_front::source::MAX_SOURCE_BYTES {
        return Err("standard input is larger than 64 MiB, the most ladderc reads from a program".into());
    }
    Ok(ladder_front::source::SourceFile::from_bytes("<stdin>", &bytes))
}
