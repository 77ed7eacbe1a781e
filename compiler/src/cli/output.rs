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
/// synced before the first is renamed into place, and the files already
/// replaced put back when a later rename fails: a failed write leaves every
/// target as it was (the files of one build, an object and its header, or
/// a project's MAIN.wpg and COMMENT.wcd, stay a pair). The renames are one
/// after another, not one step: a reader may see the first file new and
/// the second still old for that moment, and a process killed between them
/// leaves that mix (and its backups, `.ladderc-*.tmp` beside the targets).
/// Putting a file back can itself fail (the disk gone): the error then
/// says so.
pub fn write_all_atomically<'p>(files: &[(&'p Path, &[u8])]) -> Result<(), (&'p Path, std::io::Error)> {
    let mut staged = Vec::with_capacity(files.len());
    for &(target, bytes) in files {
        let file = stage(target, bytes).map_err(|error| (target, error))?;
        staged.push((target, file));
    }
    // What each replaced target was: a backup of its old content (a hard
    // link, else a copy), or nothing when there was no file.
    let mut replaced: Vec<(&'p Path, Option<tempfile::TempPath>)> = Vec::with_capacity(files.len());
    for (target, file) in staged {
        let step = backup(target).and_then(|old| {
            file.persist(target).map_err(|e| e.error)?;
            Ok(old)
        });
        match step {
            Ok(old) => replaced.push((target, old)),
            Err(error) => {
                let error = match restore(replaced) {
                    Ok(()) => error,
                    Err((path, undo)) => std::io::Error::new(
                        error.kind(),
                        format!("{error}; and {} could not be put back: {undo}", path.display()),
                    ),
                };
                return Err((target, error));
            }
        }
    }
    Ok(())
}

/// A temporary hard link to (or copy of) `target`'s present content, or
/// None when there is no file; removed when dropped.
fn backup(target: &Path) -> std::io::Result<Option<tempfile::TempPath>> {
    if !target.is_file() {
        return Ok(None);
    }
    let directory = match target.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let path = tempfile::Builder::new()
        .prefix(".ladderc-")
        .suffix(".tmp")
        .tempfile_in(directory)?
        .into_temp_path();
    // A link keeps the old file's inode whole: the rename over `target`
    // does not touch it.
    std::fs::remove_file(&path)?;
    if std::fs::hard_link(target, &path).is_err() {
        std::fs::copy(target, &path)?;
    }
    Ok(Some(path))
}

/// Puts the replaced targets back (the last first): each from its backup,
/// or removed when there was no file before.
fn restore(replaced: Vec<(&Path, Option<tempfile::TempPath>)>) -> Result<(), (&Path, std::io::Error)> {
    let mut first_error = None;
    for (target, old) in replaced.into_iter().rev() {
        let undone = match old {
            Some(old) => old.persist(target).map_err(|e| e.error),
            None => std::fs::remove_file(target),
        };
        if let Err(error) = undone {
            first_error.get_or_insert((target, error));
        }
    }
    first_error.map_or(Ok(()), Err)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("ladderc-output-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn leftovers(dir: &Path) -> Vec<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|name| name.starts_with(".ladderc-"))
            .collect()
    }

    #[test]
    fn a_failed_second_rename_puts_the_first_file_back() {
        let dir = scratch("pair");
        let (first, second, fresh) = (dir.join("MAIN.wpg"), dir.join("COMMENT.wcd"), dir.join("NEW.wpg"));
        std::fs::write(&first, b"old").unwrap();
        // A folder that is not empty cannot be renamed over.
        std::fs::create_dir_all(second.join("inside")).unwrap();
        let error = write_all_atomically(&[(&first, b"new"), (&fresh, b"new"), (&second, b"new")]).unwrap_err();
        assert_eq!(error.0, second.as_path());
        assert_eq!(std::fs::read(&first).unwrap(), b"old");
        assert!(!fresh.exists(), "a file that was not there is removed again");
        assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
        std::fs::remove_dir_all(&second).unwrap();
        write_all_atomically(&[(&first, b"new"), (&second, b"new")]).unwrap();
        assert_eq!(std::fs::read(&first).unwrap(), b"new");
        assert_eq!(std::fs::read(&second).unwrap(), b"new");
        assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
