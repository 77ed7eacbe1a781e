//! `ladderc build`: an object file with the C-ABI scan entry point, or the IR.

use super::output;
use super::status;
use crate::codegen::ObjectOptions;
use crate::diagnostics::Shown;
use clap::{Args, ValueEnum};
use std::io::Write;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub struct BuildArgs {
    /// The program: IL or a GX Works2 CSV export (`-` reads standard input).
    program: PathBuf,
    /// Output file, `-` for standard output (default: the program's name
    /// with `.o`; for `--emit ir` or a program from standard input, standard
    /// output).
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
    /// Target triple, e.g. aarch64-unknown-linux-gnu or riscv64gc-unknown-linux-gnu
    /// (default: this machine); thumbv6m/thumbv7m/thumbv7em-none-eabi(hf),
    /// armv7-unknown-linux-gnueabihf and riscv32imac-unknown-none-elf go
    /// through the C back end and the cross compiler (or write the C file).
    #[arg(long)]
    target: Option<String>,
    /// Prefix of the exported entry point `<PREFIX>scan`, so that several
    /// programs can live in one firmware.
    #[arg(long, default_value = crate::codegen::DEFAULT_PREFIX)]
    prefix: String,
    /// What to produce.
    #[arg(long, value_enum, default_value_t = Emit::Obj)]
    emit: Emit,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Emit {
    /// An object file.
    Obj,
    /// The optimised IR, as text.
    Ir,
    /// Portable C99 from the same IR, with the same entry point and C API
    /// as the object file (build it with any C compiler; link it with the
    /// runtime library).
    C,
}

pub fn run(args: &BuildArgs, shown: Shown) -> u8 {
    if let Err(message) = check_prefix(&args.prefix) {
        say_err!("error: --prefix `{}`: {message}", args.prefix);
        return status::UNUSABLE;
    }
    // A target Cranelift lacks goes through the C back end: an object from
    // the cross compiler when one is installed, else the C file and the
    // command that builds it.
    let c_target = args.target.as_deref().and_then(crate::cback::targets::c_target);
    let cross = c_target.and_then(|target| target.find_compiler().map(|compiler| (target, compiler)));
    if let (Some(target), None, Emit::Obj) = (c_target, cross, args.emit) {
        let output = args
            .output
            .clone()
            .filter(|path| !super::is_standard_stream(path))
            .unwrap_or_else(|| args.program.clone())
            .with_extension("c");
        let as_c = BuildArgs {
            program: args.program.clone(),
            output: Some(output.clone()),
            target: None,
            prefix: args.prefix.clone(),
            emit: Emit::C,
        };
        let code = run(&as_c, shown);
        if code == status::OK {
            say_err!(
                "note: no compiler for {} found (tried {}; Debian package {}): wrote the program as C to {}; \
                 build it with `{}` and link it with the runtime library built for {}",
                target.triple,
                target.compilers.join(", "),
                target.package,
                output.display(),
                target.command_line(target.compilers[0], &output.display().to_string()),
                target.triple
            );
        }
        return code;
    }
    // `-o -`, and a program read from standard input without `-o`, write
    // to standard output.
    let output = match (&args.output, args.emit) {
        (Some(path), _) if super::is_standard_stream(path) => None,
        (Some(path), _) => Some(path.clone()),
        (None, Emit::Obj) if super::is_standard_stream(&args.program) => None,
        (None, Emit::Obj) => Some(args.program.with_extension("o")),
        (None, Emit::Ir) => None,
        (None, Emit::C) if super::is_standard_stream(&args.program) => None,
        (None, Emit::C) => Some(args.program.with_extension("c")),
    };
    // Checked before compiling: a refused output is refused however the
    // program is.
    let target = match output.as_deref().map(|path| output::prepare(path, &[&args.program])) {
        None => None,
        Some(Ok(target)) => Some(target),
        Some(Err(error)) => {
            say_err!("error: {error}");
            return status::UNUSABLE;
        }
    };
    // A failed build writes nothing and removes nothing.
    let bytes = match produce(args, shown) {
        Ok(bytes) => bytes,
        Err(code) => return code,
    };
    match target {
        None => {
            use std::io::IsTerminal as _;
            if args.emit == Emit::Obj && std::io::stdout().is_terminal() {
                say_err!(
                    "error: not writing an object file to a terminal; name a file with -o (or redirect the output)"
                );
                return status::UNUSABLE;
            }
            let _ = std::io::stdout().lock().write_all(&bytes);
            status::OK
        }
        Some(path) => match output::write_atomically(&path, &bytes) {
            Ok(()) => status::OK,
            Err(error) => {
                say_err!("error: cannot write {}: {error}", path.display());
                status::FAILED
            }
        },
    }
}

fn produce(args: &BuildArgs, shown: Shown) -> Result<Vec<u8>, u8> {
    let program = super::compile_file(&args.program, shown)?;
    match args.emit {
        Emit::Ir => Ok(crate::pipeline::ir(&program).to_string().into_bytes()),
        Emit::C => {
            let options = crate::cback::COptions {
                prefix: args.prefix.clone(),
                source_name: args
                    .program
                    .file_name()
                    .map_or_else(|| "standard input".to_string(), |n| n.to_string_lossy().into_owned()),
            };
            Ok(crate::pipeline::c_source(&program, &options).into_bytes())
        }
        Emit::Obj
            if args
                .target
                .as_deref()
                .and_then(crate::cback::targets::c_target)
                .is_some() =>
        {
            let target = args.target.as_deref().and_then(crate::cback::targets::c_target);
            let Some((target, compiler)) = target.and_then(|t| t.find_compiler().map(|c| (t, c))) else {
                say_err!("error: the cross compiler went away");
                return Err(status::FAILED);
            };
            let options = crate::cback::COptions {
                prefix: args.prefix.clone(),
                source_name: args.program.display().to_string(),
            };
            target
                .compile(compiler, &crate::pipeline::c_source(&program, &options))
                .map_err(|error| {
                    say_err!("error: {error}");
                    status::FAILED
                })
        }
        Emit::Obj => {
            let options = ObjectOptions {
                target: args.target.clone(),
                prefix: args.prefix.clone(),
            };
            crate::pipeline::object(&program, &options).map_err(|error| {
                say_err!("error: {error}");
                match error {
                    // A target ladderc cannot build for is a bad argument.
                    crate::codegen::CodegenError::Target(_) => status::UNUSABLE,
                    crate::codegen::CodegenError::HostTarget(_)
                    | crate::codegen::CodegenError::Module(_)
                    | crate::codegen::CodegenError::Object(_) => status::FAILED,
                }
            })
        }
    }
}

/// A prefix for `<prefix>scan`: a C identifier start, outside the names the
/// runtime reserves (`ladder_`, except the default `ladder_program_`).
fn check_prefix(prefix: &str) -> Result<(), String> {
    let mut chars = prefix.chars();
    let Some(first) = chars.next() else {
        return Err("the prefix is empty; the entry point would be a bare `scan`".into());
    };
    if !(first.is_ascii_alphabetic() || first == '_') || !chars.all(|c| c.is_ascii_alphanumeric() || c == '_') {
        return Err("a prefix is the start of a C identifier: letters, digits and `_`, not a digit first".into());
    }
    if prefix.starts_with("ladder_") && prefix != crate::codegen::DEFAULT_PREFIX {
        return Err(format!(
            "names starting with `ladder_` belong to the runtime (ladder_begin_scan, ladder_end_scan, ladder_rt_...); \
             use another prefix such as `motor_`, or the default `{}`",
            crate::codegen::DEFAULT_PREFIX
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::check_prefix;

    #[test]
    fn prefixes() {
        for good in ["motor_", "m", "_x1", "ladder_program_", "ladderx_"] {
            assert!(check_prefix(good).is_ok(), "{good}");
        }
        for bad in ["", "1x", "a-b", "ladder_end_", "ladder_begin_", "ladder_rt_", "é"] {
            assert!(check_prefix(bad).is_err(), "{bad}");
        }
    }
}
