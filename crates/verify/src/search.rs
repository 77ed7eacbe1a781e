//! The explicit-state search: breadth first over the states the program can
//! reach from power-up, every choice of inputs and elapsed time at every
//! scan, each property checked on every transition (the image before and
//! after a scan, for `prev`, `rose` and `fell`). Breadth first, a violation
//! is found at the earliest scan it can happen; when every reachable state
//! has been visited without one, the property is proved.
//!
//! `respond` is checked on the product of the states with a small monitor:
//! the scans left for the oldest trigger still waiting for its response.

use crate::model::{Choice, Model};
use crate::property::Claim;
use rustc_hash::FxHashMap;
use std::rc::Rc;
use std::time::{Duration, Instant};

/// How far a search may go before it answers `unknown`.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Scans from power-up.
    pub depth: u32,
    pub timeout: Duration,
    /// Distinct states (with the monitor's).
    pub states: usize,
    /// Choices per scan the search enumerates.
    pub branching: u64,
    /// Bytes of the states kept.
    pub memory: usize,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            depth: 1_000_000,
            timeout: Duration::from_secs(60),
            states: 2_000_000,
            branching: 4096,
            memory: 1 << 30,
        }
    }
}

/// What the search found.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Every reachable state was visited: a never/always/respond property
    /// holds, a reach property's condition is never true.
    Exhausted,
    /// The property fails (or, for reach, its condition holds) after scan
    /// `path.len()`, driven by these choices from power-up.
    Found {
        path: Vec<Choice>,
    },
    Unknown(String),
}

/// Statistics of one search, for reports and benchmarks.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Searched {
    /// Which SAT-based engine decided, and where (`IC3 in 5 frames`),
    /// when they did; `None` for the explicit-state search.
    pub by_sat: Option<String>,
    pub states: usize,
    pub transitions: u64,
    pub depth: u32,
    /// Whether the condition of an implication (`always A -> B`) or the
    /// trigger of a `respond` was ever true: false on a proof means the
    /// property holds only vacuously.
    pub condition_seen: bool,
}

struct Node {
    key: Rc<[u8]>,
    monitor: u32,
    parent: usize,
    choice: usize,
}

/// Searches `model` for a transition that breaks `claim` (or, for reach,
/// satisfies it).
pub fn search(model: &Model, claim: &Claim, limits: &Limits) -> (Outcome, Searched) {
    let mut stats = Searched::default();
    let branching = model.branching();
    if branching > limits.branching {
        let choices = if branching == u64::MAX {
            "more than 10^19".to_string()
        } else {
            branching.to_string()
        };
        return (
            Outcome::Unknown(format!(
                "{choices} choices of inputs per scan from {} inputs that reach the property; the explicit-state search takes at most {} (name fewer inputs with `input`, or narrow their ranges)",
                model.inputs.len(),
                limits.branching
            )),
            stats,
        );
    }
    let choices = model.choices();
    let started = Instant::now();
    let mut nodes: Vec<Node> = Vec::new();
    // Each state's bytes once, shared by its node and the set of seen ones.
    let mut seen: FxHashMap<(Rc<[u8]>, u32), ()> = FxHashMap::default();
    let bytes_per_state = model.state_size() + std::mem::size_of::<Node>() + 64;
    let mut before = model.power_up.clone();
    let mut work = model.power_up.clone();
    // The power-up image is not a state after a scan: it is expanded first
    // (`None`) and never entered again.
    let mut frontier: Vec<Option<usize>> = vec![None];
    let mut depth = 0u32;
    while !frontier.is_empty() {
        if depth >= limits.depth {
            return (
                Outcome::Unknown(format!("depth {} reached (--depth)", limits.depth)),
                stats,
            );
        }
        depth += 1;
        stats.depth = depth;
        let parents = std::mem::take(&mut frontier);
        for parent in parents {
            if started.elapsed() > limits.timeout {
                return (
                    Outcome::Unknown(format!("timeout after {} s (--timeout)", limits.timeout.as_secs())),
                    stats,
                );
            }
            let monitor = match parent {
                None => {
                    *before = *model.power_up;
                    0
                }
                Some(p) => {
                    model.restore(&nodes[p].key, &mut before);
                    nodes[p].monitor
                }
            };
            for (index, choice) in choices.iter().enumerate() {
                match parent {
                    None => *work = *model.power_up,
                    Some(p) => model.restore(&nodes[p].key, &mut work),
                }
                if !model.apply_inputs(&mut work, choice) {
                    continue;
                }
                model.scan(&mut work, choice.elapsed_ms);
                stats.transitions += 1;
                let step = check(claim, &before, &work, monitor, &mut stats.condition_seen);
                let found = match step {
                    Step::Found => true,
                    Step::Monitor(_) => false,
                };
                let monitor = match step {
                    Step::Found => 0,
                    Step::Monitor(m) => m,
                };
                if found {
                    let mut path = vec![choice.clone()];
                    let mut at = parent;
                    while let Some(p) = at {
                        path.push(choices[nodes[p].choice].clone());
                        at = (nodes[p].parent != usize::MAX).then_some(nodes[p].parent);
                    }
                    path.reverse();
                    stats.states = nodes.len();
                    return (Outcome::Found { path }, stats);
                }
                let key: Rc<[u8]> = Rc::from(model.key(&work));
                if seen.contains_key(&(Rc::clone(&key), monitor)) {
                    continue;
                }
                if nodes.len() >= limits.states {
                    stats.states = nodes.len();
                    return (
                        Outcome::Unknown(format!("{} states visited (the search's limit)", limits.states)),
                        stats,
                    );
                }
                if nodes.len().saturating_mul(bytes_per_state) >= limits.memory {
                    stats.states = nodes.len();
                    return (
                        Outcome::Unknown(format!(
                            "{} states of {} bytes fill the search's {} MB",
                            nodes.len(),
                            model.state_size(),
                            limits.memory >> 20
                        )),
                        stats,
                    );
                }
                seen.insert((Rc::clone(&key), monitor), ());
                nodes.push(Node {
                    key,
                    monitor,
                    parent: parent.unwrap_or(usize::MAX),
                    choice: index,
                });
                frontier.push(Some(nodes.len() - 1));
                stats.states = nodes.len();
            }
        }
    }
    (Outcome::Exhausted, stats)
}

pub(crate) enum Step {
    /// The transition breaks the property (reach: satisfies it).
    Found,
    /// It does not; the monitor's next value.
    Monitor(u32),
}

/// Checks one transition. The monitor of `respond` is the number of scans
/// the oldest waiting trigger still allows after this one, 0 for none.
pub(crate) fn check(
    claim: &Claim,
    before: &ladder_runtime::Memory,
    now: &ladder_runtime::Memory,
    monitor: u32,
    condition_seen: &mut bool,
) -> Step {
    match claim {
        Claim::Never(e) => {
            if e.holds(before, now) {
                return Step::Found;
            }
            Step::Monitor(0)
        }
        Claim::Always(e) => {
            if let crate::expr::Expr::Implies(condition, _) = e {
                *condition_seen |= condition.holds(before, now);
            }
            if e.holds(before, now) {
                Step::Monitor(0)
            } else {
                Step::Found
            }
        }
        Claim::Reach(e) => {
            if e.holds(before, now) {
                Step::Found
            } else {
                Step::Monitor(0)
            }
        }
        Claim::Respond {
            trigger,
            response,
            within,
        } => {
            let triggered = trigger.holds(before, now);
            *condition_seen |= triggered;
            if response.holds(before, now) {
                return Step::Monitor(0);
            }
            // The oldest waiting trigger: its window ends with this scan
            // when it allowed one more.
            let waiting = match monitor {
                0 => None,
                1 => return Step::Found,
                left => Some(left - 1),
            };
            let fresh = if triggered {
                if *within == 0 {
                    return Step::Found;
                }
                Some(*within)
            } else {
                None
            };
            Step::Monitor(match (waiting, fresh) {
                (Some(a), Some(b)) => a.min(b),
                (Some(a), None) | (None, Some(a)) => a,
                (None, None) => 0,
            })
        }
    }
}
