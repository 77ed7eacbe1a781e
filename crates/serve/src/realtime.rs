//! The scan thread's wake-up precision. Always: a timer slack of 1 µs for
//! the scan thread (Linux otherwise lets a sleep end up to 50 µs late to
//! batch wake-ups). With `--realtime`: SCHED_FIFO for the scan thread only
//! (the servers keep normal priority, so a client cannot starve a scan but
//! neither can a scan starve the servers for longer than it takes), and
//! the process's memory locked so a page fault never delays a scan, and the
//! last 250 µs before a scan is due spun rather than slept. Where
//! the system does not permit it, a line says why and scanning goes on.

/// With `--realtime`, the scan thread sleeps until this long before a
/// scan is due and spins the rest (at most a tenth of the period): the
/// OS's wake-up latency then no longer delays the scan.
pub const SPIN: std::time::Duration = std::time::Duration::from_micros(250);

/// SCHED_FIFO priority of the scan thread: above normal threads, below the
/// kernel's own real-time threads (which use 50 and up).
#[cfg(target_os = "linux")]
const SCAN_PRIORITY: i32 = 40;

/// Prepares the calling (scan) thread; returns lines for the log.
#[cfg(target_os = "linux")]
pub fn prepare_scan_thread(realtime: bool) -> Vec<String> {
    // SAFETY: prctl with PR_SET_TIMERSLACK takes a plain integer and
    // changes only the calling thread's timer slack.
    unsafe {
        libc::prctl(libc::PR_SET_TIMERSLACK, 1 as libc::c_ulong);
    }
    fixed_mmap_threshold();
    if !realtime {
        return Vec::new();
    }
    let mut lines = Vec::new();
    // SAFETY: mlockall takes flags only; it fails cleanly without permission.
    let locked = unsafe { libc::mlockall(libc::MCL_CURRENT | libc::MCL_FUTURE) };
    if locked == 0 {
        lines.push("realtime: memory locked".to_string());
    } else {
        lines.push(format!(
            "realtime: cannot lock memory ({}); raise `ulimit -l` or grant CAP_IPC_LOCK",
            std::io::Error::last_os_error()
        ));
    }
    let param = libc::sched_param {
        sched_priority: SCAN_PRIORITY,
    };
    // SAFETY: pthread_self is the calling thread; param outlives the call.
    let scheduled = unsafe { libc::pthread_setschedparam(libc::pthread_self(), libc::SCHED_FIFO, &param) };
    if scheduled == 0 {
        lines.push(format!("realtime: scan thread at SCHED_FIFO priority {SCAN_PRIORITY}"));
    } else {
        lines.push(format!(
            "realtime: cannot use SCHED_FIFO ({}); run as root, grant CAP_SYS_NICE or raise `ulimit -r`; \
             scanning at normal priority",
            std::io::Error::from_raw_os_error(scheduled)
        ));
    }
    lines
}

/// Large buffers (an event stream's samples, an image) are mapped for
/// themselves and given back when freed. glibc otherwise raises its mapping
/// threshold after the first such free and serves later ones from its heap,
/// where what is freed stays resident (all of it with `--realtime`'s locked
/// memory): a server whose event streams come and go grew by a few MB every
/// few minutes.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn fixed_mmap_threshold() {
    // SAFETY: mallopt takes two integers and changes the allocator's
    // parameters only; setting M_MMAP_THRESHOLD is documented as safe at
    // any time.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 128 * 1024);
    }
}

#[cfg(all(target_os = "linux", not(target_env = "gnu")))]
fn fixed_mmap_threshold() {}

#[cfg(not(target_os = "linux"))]
pub fn prepare_scan_thread(realtime: bool) -> Vec<String> {
    if realtime {
        vec!["realtime: only available on Linux; scanning at normal priority".to_string()]
    } else {
        Vec::new()
    }
}
