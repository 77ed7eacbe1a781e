//! Ratios of CPU time measured in paired rounds.
//!
//! Criterion times each benchmark in turn, for seconds each, so a ratio of
//! two of its estimates also measures how the machine changed between them:
//! on the shared 2-core machines this project runs on, the same object's
//! time moves by a quarter between back-to-back runs. A paired round times
//! both sides within a few tens of milliseconds of each other, in the
//! thread's own CPU time (time the machine gave to other work is not
//! counted), and alternates which side goes first; the median of the
//! rounds' ratios is what a drift of the machine moves least.

use std::time::Duration;

/// The ratios of the rounds, summarised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairedRatio {
    pub rounds: usize,
    pub median: f64,
    /// The middle half of the rounds' ratios lies between these.
    pub lower_quartile: f64,
    pub upper_quartile: f64,
}

impl PairedRatio {
    /// The summary of the rounds' ratios `a / b` (none of them NaN), or
    /// `None` when there are none.
    pub fn of(mut ratios: Vec<f64>) -> Option<PairedRatio> {
        if ratios.is_empty() {
            return None;
        }
        ratios.sort_by(f64::total_cmp);
        Some(PairedRatio {
            rounds: ratios.len(),
            median: quantile(&ratios, 0.5),
            lower_quartile: quantile(&ratios, 0.25),
            upper_quartile: quantile(&ratios, 0.75),
        })
    }
}

/// The `q` quantile of sorted, non-empty `values`, interpolated between
/// the two nearest ranks.
fn quantile(values: &[f64], q: f64) -> f64 {
    let position = q * (values.len() - 1) as f64;
    let below = position.floor() as usize;
    let above = position.ceil() as usize;
    let weight = position - below as f64;
    values[below] * (1.0 - weight) + values[above] * weight
}

/// The CPU time the calling thread has used.
pub fn thread_cpu_time() -> Duration {
    let mut now = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `now` is a valid timespec for the call to fill in.
    let status = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut now) };
    assert_eq!(status, 0, "the thread's CPU clock is readable");
    Duration::new(now.tv_sec as u64, now.tv_nsec as u32)
}

/// The CPU time of `calls` calls of `f`.
fn timed(f: &mut impl FnMut(), calls: u64) -> Duration {
    let start = thread_cpu_time();
    for _ in 0..calls {
        f();
    }
    thread_cpu_time().saturating_sub(start)
}

/// How many calls of `f` take about `target` of CPU time (at least one).
fn calls_for(f: &mut impl FnMut(), target: Duration) -> u64 {
    let mut calls = 1u64;
    loop {
        let time = timed(f, calls);
        if time >= target / 4 || calls >= 1 << 40 {
            let per_call = time.as_secs_f64() / calls as f64;
            return ((target.as_secs_f64() / per_call.max(1e-12)) as u64).max(1);
        }
        calls *= 4;
    }
}

/// The ratio of CPU time per call of `a` to that of `b`, from `rounds`
/// rounds that each time both for about `round_time`, `a` first in even
/// rounds and `b` first in odd ones.
pub fn paired_cpu_ratio(
    mut a: impl FnMut(),
    mut b: impl FnMut(),
    rounds: usize,
    round_time: Duration,
) -> Option<PairedRatio> {
    let calls_a = calls_for(&mut a, round_time);
    let calls_b = calls_for(&mut b, round_time);
    let mut ratios = Vec::with_capacity(rounds);
    for round in 0..rounds {
        let (time_a, time_b) = if round % 2 == 0 {
            let time_a = timed(&mut a, calls_a);
            (time_a, timed(&mut b, calls_b))
        } else {
            let time_b = timed(&mut b, calls_b);
            (timed(&mut a, calls_a), time_b)
        };
        let per_call_b = time_b.as_secs_f64() / calls_b as f64;
        if per_call_b > 0.0 {
            ratios.push(time_a.as_secs_f64() / calls_a as f64 / per_call_b);
        }
    }
    PairedRatio::of(ratios)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_of_an_odd_number_of_rounds() {
        let ratio = PairedRatio::of(vec![0.9, 0.7, 0.8, 1.4, 0.75]).unwrap();
        assert_eq!(ratio.rounds, 5);
        assert_eq!(ratio.median, 0.8);
        assert_eq!(ratio.lower_quartile, 0.75);
        assert_eq!(ratio.upper_quartile, 0.9);
    }

    #[test]
    fn summary_interpolates_between_ranks() {
        let ratio = PairedRatio::of(vec![4.0, 1.0, 3.0, 2.0]).unwrap();
        assert_eq!(ratio.median, 2.5);
        assert_eq!(ratio.lower_quartile, 1.75);
        assert_eq!(ratio.upper_quartile, 3.25);
    }

    #[test]
    fn no_rounds_no_summary() {
        assert_eq!(PairedRatio::of(Vec::new()), None);
    }

    #[test]
    fn the_thread_clock_counts_work() {
        let start = thread_cpu_time();
        let mut sum = 0u64;
        for i in 0..2_000_000u64 {
            sum = std::hint::black_box(sum.wrapping_add(i * i));
        }
        assert!(sum > 0);
        assert!(
            thread_cpu_time() > start,
            "the CPU clock did not move over two million additions"
        );
    }
}
