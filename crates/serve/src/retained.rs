//! `--retain` in a running server: the latched devices restored from the
//! retain file before the first scan (and what start-up says of them), and
//! the thread that writes them back every interval and once more at stop.
//! The file itself (its format, atomic writes) is `retain.rs`.

use super::announce;
use super::retain::{self, LatchRange, RetainFile};
use super::shared::Shared;
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// The latched values the file holds, within the ranges latched now; a
/// file that cannot be read is an error that stops everything before a
/// scan.
pub fn restore(file: &RetainFile) -> Result<Vec<(LatchRange, Vec<i32>)>, String> {
    if file.remove_leftover() {
        announce(&format!(
            "retain: removed {}, left by a save that was cut short",
            file.temporary().display()
        ));
    }
    match file.load()? {
        retain::Restored::Fresh => {
            announce(&format!(
                "retain: {} does not exist yet; the latched devices start cleared",
                file.path.display()
            ));
            Ok(Vec::new())
        }
        retain::Restored::Values(records) => {
            // Only what is latched now comes back (`--latch`).
            let (records, dropped) = retain::within(records, &file.ranges);
            let names = |ranges: &mut dyn Iterator<Item = LatchRange>| {
                ranges.map(|range| range.to_string()).collect::<Vec<_>>().join(", ")
            };
            announce(&format!(
                "retain: restored {} from {}",
                match names(&mut records.iter().map(|(range, _)| *range)) {
                    none if none.is_empty() => "nothing".to_string(),
                    some => some,
                },
                file.path.display()
            ));
            if !dropped.is_empty() {
                announce(&format!(
                    "retain: the file also holds {}, which are not latched now (--latch): not restored",
                    names(&mut dropped.into_iter())
                ));
            }
            Ok(records)
        }
    }
}

/// Starts the thread of `keep`.
pub fn start_saver(file: &RetainFile, interval: Duration, shared: &Arc<Shared>) -> JoinHandle<()> {
    let shared = Arc::clone(shared);
    let file = file.clone();
    std::thread::spawn(move || keep(&file, interval, &shared))
}

/// `--retain`: writes the latched devices of the published image every
/// `interval` and once more when the server stops. Nothing is written
/// before the first scan has published an image (the restored values would
/// otherwise be overwritten by an empty image); a failed write is reported
/// once and tried again at the next interval.
fn keep(file: &RetainFile, interval: Duration, shared: &Shared) {
    let mut last_error = None;
    // What the file holds: an unchanged image is not written again (a
    // controller's flash wears with every write).
    let mut written: Option<Vec<u8>> = None;
    let mut next = Instant::now() + interval;
    loop {
        let stopping = shared.wait_stop_until(next);
        next += interval;
        if !shared.published() {
            if stopping {
                return;
            }
            continue;
        }
        let image = shared.image();
        let bytes = retain::encode(&image, &file.ranges);
        if written.as_ref() == Some(&bytes) {
            if stopping {
                return;
            }
            continue;
        }
        let result = file.write(&bytes).map_err(|e| e.to_string());
        if result.is_ok() {
            written = Some(bytes);
        }
        if let Err(error) = &result {
            if last_error.as_ref() != Some(error) {
                use std::io::Write as _;
                let _ = writeln!(
                    std::io::stderr(),
                    "retain: cannot write {}: {error}",
                    file.path.display()
                );
            }
        }
        last_error = result.err();
        if stopping {
            if last_error.is_none() {
                announce(&format!("retain: saved to {}", file.path.display()));
            }
            return;
        }
    }
}
