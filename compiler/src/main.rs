//! The `ladderc` binary: a thin shell around `ladderc::cli`.

fn main() -> std::process::ExitCode {
    std::process::ExitCode::from(ladderc::cli::main_with_args(std::env::args_os()))
}
