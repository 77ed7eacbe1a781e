//! Writing an output file without ever destroying anything: the output may
//! not be one of the inputs (also through links), only a regular file (or
//! nothing) is replaced, a symbolic link is written through, and a failed
//! command leaves whatever was there untouched.

use std::io::Write;
use std::path::{Path, PathBuf};

/// Why an output path cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("the output `{output}` is the input `{input}`; writing it would destroy it")]
    SameAsInput { output: PathBuf, input: PathBuf },
    #[error("the output `{0}` is in a folder that does not exist")]
    NoFolder(PathBuf),
    #[error("the output `{0}` is {1}; ladderc only replaces regular files")]
    NotRegular(PathBuf, &'static str),
    #[error("the output `{0}` is a symbolic link to a file that does not exist")]
    DanglingLink(PathBuf),
    #[error("cannot use the output `{0}`: {1}")]
    Io(PathBuf, std::io::Error),
}

/// What kind of file a path names, for messages.
fn kind_of(metadata: &std::fs::Metadata) -> &'static str {
    let file_type = metadata.file_type();
    if file_type.is_dir() {
        return "a directory";
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if file_type.is_fifo() {
            return "a named pipe";
        }
        if file_type.is_char_device() || file_type.is_block_device() {
            return "a device";
        }
        if file_type.is_socket() {
            return "a socket";
        }
    }
    "not a regular file"
}

/// Whether two existing paths are the same file (same device and inode on
/// Unix, so hard links count; the same canonical path elsewhere).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(a), Ok(b)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return a.dev() == b.dev() && a.ino() == b.ino();
        }
    }
    matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
}

/// Checks that `output` may be written and returns the file to replace:
/// `output` itself, or the file a symbolic link at `output` points to.
pub fn prepare(output: &Path, inputs: &[&Path]) -> Result<PathBuf, OutputError> {
    let io = |e| OutputError::Io(output.to_path_buf(), e);
    let target = match std::fs::symlink_metadata(output) {
        Ok(metadata) if metadata.file_type().is_symlink() => match output.canonicalize() {
            Ok(target) => target,
            Err(_) => return Err(OutputError::DanglingLink(output.to_path_buf())),
        },
        Ok(_) => output.to_path_buf(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            // Found out now, before the work, not when the file is written.
            let folder = match output.parent() {
                Some(parent) if !parent.as_os_str().is_empty() => parent,
                _ => Path::new("."),
            };
            if !folder.is_dir() {
                return Err(OutputError::NoFolder(output.to_path_buf()));
            }
            return Ok(output.to_path_buf());
        }
        Err(e) => return Err(io(e)),
    };
    let metadata = std::fs::metadata(&target).map_err(io)?;
    if !metadata.file_type().is_file() {
        return Err(OutputError::NotRegular(output.to_path_buf(), kind_of(&metadata)));
    }
    for input in inputs {
        if same_file(&target, input) {
            return Err(OutputError::SameAsInput {
                output: output.to_path_buf(),
                input: input.to_path_buf(),
            });
        }
    }
    Ok(target)
}

/// Writes `bytes` to a temporary file next to `target` and renames it into
/// place: readers see the old file or the whole new one, never a part, and
/// nothing but `target` (a regular file, or nothing, by `prepare`) is
/// replaced. On failure the temporary file is removed and `target` is left
/// as it was.
pub fn write_atomically(target: &Path, bytes: &[u8]) -> std::io::Result<()> {
    stage(target, bytes)?.persist(target).map_err(|e| e.error)?;
    Ok(())
}

/// A temporary file beside `target` holding `bytes`, synced.
fn stage(target: &Path, bytes: &[u8]) -> std::io::Result<tempfile::NamedTempFile> {
    let directory = match target.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".ladderc-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // An object file is an ordinary file, not a private temporary one.
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    let mut file = builder.tempfile_in(directory)?;
    file.write_all(bytes)?;
    file.as_file().sync_all()?;
    Ok(file)
}

/// Writes every file as `write_atomically` does, all of them written and
/// synced before the first is renamed into place: a failed write replaces
/// none (the files of one build, an object and its header, stay a pair).
pub fn write_all_atomically<'p>(files: &[(&'p Path, &[u8])]) -> Result<(), (&'p Path, std::io::Error)> {
    let mut staged = Vec::with_capacity(files.len());
    for &(target, bytes) in files {
        let file = stage(target, bytes).map_err(|error| (target, error))?;
        staged.push((target, file));
    }
    for (target, file) in staged {
        file.persist(target).map_err(|e| (target, e.error))?;
    }
    Ok(())
}
