//! `--watch-file`: the program file (or a GX Developer project's MAIN.wpg)
//! watched for online change. A change is
//! taken once the file has stopped changing; a version that compiles is
//! offered to the scan thread, one that does not (or drives nothing) is
//! reported on stderr and the running program goes on.

use super::announce;
use super::change::{self, Refusal};
use super::shared::Shared;
use ladder_front::source::SourceFile;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Starts the thread that watches `path` (it ends when the server stops).
pub fn start(path: PathBuf, shared: &Arc<Shared>, native: bool, settle: Duration) {
    let shared = Arc::clone(shared);
    std::thread::spawn(move || watch(&path, &shared, native, settle));
}

/// When the file's modification time or length changed: the length too,
/// for two writes within a coarse file-system clock tick.
type Stamp = Option<(Option<std::time::SystemTime>, u64)>;

fn stamp(path: &Path) -> Stamp {
    std::fs::metadata(path).ok().map(|m| (m.modified().ok(), m.len()))
}

/// When the program file changes, compiles it and offers it for online
/// change. For a GX Developer project, its MAIN.wpg is watched and the
/// project's listing offered.
fn watch(named: &Path, shared: &Shared, native: bool, settle: Duration) {
    let project = ladder_front::gxdev::locate(named);
    let path = project.as_ref().map_or(named, |p| p.program.as_path());
    // The source and what tells one version from the next: the file's
    // bytes, or for a project its listing (or the error that it cannot be
    // decoded, which is offered as well, so that it is reported). A file
    // that cannot be read (gone for a moment while an editor saves it) is
    // no version.
    let read = || -> Option<(Vec<u8>, SourceFile)> {
        match &project {
            Some(_) => {
                let source = SourceFile::read(named).ok()?;
                let mut key = source.text.clone().into_bytes();
                key.extend(source.decode_error.iter().flat_map(|e| e.bytes()));
                Some((key, source))
            }
            None => {
                let bytes = std::fs::read(path).ok()?;
                let source = SourceFile::from_bytes(path.display().to_string(), &bytes);
                Some((bytes, source))
            }
        }
    };
    let mut seen = stamp(path);
    let mut taken: Option<Vec<u8>> = read().map(|(key, _)| key);
    while !shared.stopping() {
        std::thread::sleep(Duration::from_millis(200));
        let now = stamp(path);
        if now == seen {
            continue;
        }
        let Some(last) = settled(path, now, shared, settle) else {
            return;
        };
        seen = last;
        let Some((key, source)) = read() else {
            continue;
        };
        // Saved again as it was: nothing to change.
        if taken.as_deref() == Some(key.as_slice()) {
            continue;
        }
        taken = Some(key);
        offer(path, &source, shared, native);
    }
}

/// A change is taken only once the file has stopped changing for `settle`
/// (an editor may write a file in parts; a part that happens to compile
/// must not run): the stamp it settled at, or None when the server stops.
fn settled(path: &Path, changed: Stamp, shared: &Shared, settle: Duration) -> Option<Stamp> {
    let mut last = changed;
    let mut still_since = Instant::now();
    while still_since.elapsed() < settle {
        if shared.stopping() {
            return None;
        }
        std::thread::sleep(Duration::from_millis(100));
        let now = stamp(path);
        if now != last {
            last = now;
            still_since = Instant::now();
        }
    }
    Some(last)
}

/// Compiles the file's new text and offers it to the scan thread, or says
/// on stderr why not.
fn offer(path: &Path, source: &SourceFile, shared: &Shared, native: bool) {
    match change::accept_source(source, false, native) {
        Ok(loaded) => {
            if shared.offer(loaded) {
                announce(&format!("{}: changed, swapping it in", path.display()));
            }
        }
        Err(Refusal::DrivesNothing(shown)) => {
            let _ = writeln!(
                std::io::stderr(),
                "{shown}{}: drives nothing (W0004); the running program goes on",
                path.display()
            );
        }
        Err(Refusal::Native(error)) => {
            let _ = writeln!(std::io::stderr(), "{}: {error}", path.display());
        }
        Err(Refusal::DoesNotCompile(shown)) => {
            let _ = writeln!(
                std::io::stderr(),
                "{shown}{}: does not compile; the running program goes on",
                path.display()
            );
        }
    }
}
