//! `ladderc build`: an object file with the C-ABI scan entry point, or the IR.

use super::status;
use crate::codegen::ObjectOptions;
use clap::{Args, ValueEnum};
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct BuildArgs {
    /// The instruction-list program.
    program: PathBuf,
    /// Output file (default: the program's name with `.o`; for `--emit ir`,
    /// standard output).
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
    /// Target triple, e.g. aarch64-unknown-linux-gnu or riscv64gc-unknown-linux-gnu
    /// (default: this machine).
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
}

pub fn run(args: &BuildArgs) -> u8 {
    let output = match (&args.output, args.emit) {
        (Some(path), _) => Some(path.clone()),
        (None, Emit::Obj) => Some(args.program.with_extension("o")),
        (None, Emit::Ir) => None,
    };
    if !is_c_identifier_prefix(&args.prefix) {
        say_err!(
            "error: --prefix `{}` must start a C identifier (letters, digits, `_`)",
            args.prefix
        );
        return status::UNUSABLE;
    }
    let bytes = match produce(args) {
        Ok(bytes) => bytes,
        Err(code) => {
            // A failed build leaves no output behind, not even an old one.
            if let Some(path) = &output {
                let _ = std::fs::remove_file(path);
            }
            return code;
        }
    };
    match output {
        None => {
            let _ = std::io::stdout().lock().write_all(&bytes);
            status::OK
        }
        Some(path) => match write_atomically(&path, &bytes) {
            Ok(()) => status::OK,
            Err(error) => {
                say_err!("error: cannot write {}: {error}", path.display());
                status::FAILED
            }
        },
    }
}

fn produce(args: &BuildArgs) -> Result<Vec<u8>, u8> {
    let program = super::compile_file(&args.program)?;
    match args.emit {
        Emit::Ir => Ok(crate::pipeline::ir(&program).to_string().into_bytes()),
        Emit::Obj => {
            let options = ObjectOptions {
                target: args.target.clone(),
                prefix: args.prefix.clone(),
            };
            crate::pipeline::object(&program, &options).map_err(|error| {
                say_err!("error: {error}");
                status::FAILED
            })
        }
    }
}

/// Writes `bytes` to a temporary file next to `path` and renames it into
/// place: readers see the old file or the whole new one, never a part.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let directory = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // An object file is an ordinary file, not a private temporary one.
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    let mut file = builder.tempfile_in(directory)?;
    file.write_all(bytes)?;
    file.as_file().sync_all()?;
    file.persist(path).map_err(|e| e.error)?;
    Ok(())
}

fn is_c_identifier_prefix(prefix: &str) -> bool {
    let mut chars = prefix.chars();
    match chars.next() {
        None => true,
        Some(first) => {
            (first.is_ascii_alphabetic() || first == '_') && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
        }
    }
}
