//! IC3 / property-directed reachability (Bradley 2011; Een, Mishchenko,
//! Brayton 2011): proves the properties that hold but are not k-inductive,
//! such as the interlocks of step sequences, by learning clauses that hold
//! in every state reachable within i scans (frame F_i) until two frames
//! agree: then their clauses are an inductive invariant that excludes
//! every bad state.
//!
//! One solver holds one copy of the scan (current state, inputs, next
//! state); frame i's clauses carry an activation literal, and a query of
//! F_i assumes the literals of frames i and above. F_0 is the power-up
//! state itself. A counterexample's length is returned; BMC at that length
//! gives its inputs (`bmc::bmc_at`).

use super::aig::Aig;
use super::sat::{SatLit, Unroller};
use super::system::System;
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::time::Instant;

/// What IC3 found.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Found {
    Holds,
    /// `bad` is ON after this many scans from power-up.
    FailsAt(usize),
    Unknown(String),
}

/// A cube over the state latches: (latch position in `Pdr::state`, value).
type Cube = Vec<(usize, bool)>;

struct Pdr<'a> {
    u: Unroller<'a>,
    /// Current-state and next-state literal of each state latch.
    current: Vec<SatLit>,
    next: Vec<SatLit>,
    init: Vec<bool>,
    /// Blocked cubes by the highest frame they are known to hold in
    /// (frames[0] stays empty; F_i is every level >= i).
    frames: Vec<Vec<Cube>>,
    activation: Vec<SatLit>,
    bad: SatLit,
    /// The free inputs of the scan, for lifting predecessors.
    inputs: Vec<SatLit>,
}

/// IC3 run a frame at a time, so that BMC can take turns with it.
pub struct Ic3<'a> {
    p: Pdr<'a>,
    k: usize,
    /// The bad latch's position among the state latches.
    bad_latch: Option<usize>,
}

impl<'a> Ic3<'a> {
    pub fn new(system: &'a System, deadline: Instant) -> Ic3<'a> {
        let aig: &Aig = &system.aig;
        let cone = aig.cone(&[system.bad]);
        let mut u = Unroller::new(aig, deadline, false);
        let mut current = Vec::new();
        let mut next = Vec::new();
        let mut init = Vec::new();
        let mut bad_latch = None;
        for latch in &aig.latches {
            if !cone[latch.node as usize] {
                continue;
            }
            if latch.node == system.bad.node() {
                bad_latch = Some(current.len());
            }
            current.push(u.lit(0, super::aig::Lit(latch.node * 2)));
            next.push(u.lit(0, latch.next));
            init.push(latch.init);
        }
        let inputs = u.encoded_inputs(0);
        let bad = u.lit(0, system.bad);
        let mut p = Pdr {
            u,
            current,
            next,
            init,
            inputs,
            frames: vec![Vec::new()],
            activation: Vec::new(),
            bad,
        };
        let unused = p.u.fresh();
        p.activation.push(unused);
        p.new_frame();
        Ic3 { p, k: 1, bad_latch }
    }

    /// One frame: block every bad state of F_k, then push clauses forward.
    /// `None` when there is no answer yet.
    pub fn step(&mut self) -> Option<Found> {
        let (p, k) = (&mut self.p, self.k);
        loop {
            let mut assumptions = p.frame_assumptions(k);
            assumptions.push(p.bad);
            match p.u.solve(&assumptions) {
                None => return Some(Found::Unknown(super::bmc::timeout())),
                Some(false) => break,
                Some(true) => {
                    // A bad state is any with the bad latch ON.
                    let cube = match self.bad_latch {
                        Some(b) => vec![(b, true)],
                        None => p.model_cube(),
                    };
                    match p.block(cube, k) {
                        Ok(None) => {}
                        Ok(Some(length)) => return Some(Found::FailsAt(length)),
                        Err(why) => return Some(Found::Unknown(why)),
                    }
                }
            }
        }
        // Push clauses forward; two equal frames end it.
        p.new_frame();
        for i in 1..=k {
            let cubes = p.frames[i].clone();
            for cube in cubes {
                match p.holds_after(&cube, i) {
                    None => return Some(Found::Unknown(super::bmc::timeout())),
                    Some(true) => {
                        p.frames[i].retain(|c| c != &cube);
                        p.add_blocked(cube, i + 1);
                    }
                    Some(false) => {}
                }
            }
            if p.frames[i].is_empty() {
                return Some(Found::Holds);
            }
        }
        self.k += 1;
        None
    }

    /// Frames so far.
    pub fn frames(&self) -> usize {
        self.k
    }

    /// The frames' sizes, for tracing.
    pub fn describe(&self) -> String {
        let sizes: Vec<String> = self.p.frames.iter().skip(1).map(|f| f.len().to_string()).collect();
        let literals: usize = self.p.frames.iter().flatten().map(Vec::len).sum();
        format!(
            "frame {}, {} state bits, clauses per frame [{}], {literals} literals",
            self.k,
            self.p.current.len(),
            sizes.join(" ")
        )
    }
}

/// An obligation: a cube to block at a frame, and how many scans lead
/// from it to a bad state.
struct Obligation {
    cube: Cube,
    to_bad: usize,
}

impl Pdr<'_> {
    fn new_frame(&mut self) {
        self.frames.push(Vec::new());
        let a = self.u.fresh();
        self.activation.push(a);
    }

    /// Assumptions that make the solver's current state range over F_i.
    fn frame_assumptions(&self, i: usize) -> Vec<SatLit> {
        if i == 0 {
            return self
                .current
                .iter()
                .zip(&self.init)
                .map(|(&l, &v)| if v { l } else { !l })
                .collect();
        }
        self.activation[i..].to_vec()
    }

    fn model_cube(&self) -> Cube {
        self.current
            .iter()
            .enumerate()
            .map(|(i, &l)| (i, self.u.value(l)))
            .collect()
    }

    fn meets_init(&self, cube: &Cube) -> bool {
        cube.iter().all(|&(i, v)| self.init[i] == v)
    }

    fn add_blocked(&mut self, cube: Cube, frame: usize) {
        let mut clause: Vec<SatLit> = cube
            .iter()
            .map(|&(i, v)| if v { !self.current[i] } else { self.current[i] })
            .collect();
        clause.push(!self.activation[frame]);
        self.u.add_clause(&clause);
        self.frames[frame].push(cube);
    }

    /// Whether `cube`'s states have no predecessor in F_i outside the
    /// cube (the clause ¬cube holds after a scan from F_i): Some(true).
    fn holds_after(&mut self, cube: &Cube, i: usize) -> Option<bool> {
        match self.relative(cube, i) {
            Relative::Stopped => None,
            Relative::Unsat(_) => Some(true),
            Relative::Sat(_) => Some(false),
        }
    }

    /// SAT?(F_i ∧ ¬cube ∧ T ∧ cube'): a predecessor, or the part of the
    /// cube the unsat core kept.
    fn relative(&mut self, cube: &Cube, i: usize) -> Relative {
        let temporary = self.u.fresh();
        let mut clause: Vec<SatLit> = cube
            .iter()
            .map(|&(j, v)| if v { !self.current[j] } else { self.current[j] })
            .collect();
        clause.push(!temporary);
        self.u.add_clause(&clause);
        let mut assumptions = self.frame_assumptions(i);
        assumptions.push(temporary);
        let primed: Vec<SatLit> = cube
            .iter()
            .map(|&(j, v)| if v { self.next[j] } else { !self.next[j] })
            .collect();
        assumptions.extend(&primed);
        let answer = match self.u.solve(&assumptions) {
            None => Relative::Stopped,
            Some(true) => Relative::Sat(self.lift(cube)),
            Some(false) => Relative::Unsat(
                cube.iter()
                    .zip(&primed)
                    .filter(|(_, &p)| self.u.in_core(p))
                    .map(|(&c, _)| c)
                    .collect(),
            ),
        };
        // The temporary clause is switched off for good.
        self.u.add_clause(&[!temporary]);
        answer
    }

    /// The model's predecessor of `successor`, with only the state bits
    /// that, with the model's inputs, force the scan into `successor`
    /// (the unsat core of "this state and these inputs, and a successor
    /// outside the cube").
    fn lift(&mut self, successor: &Cube) -> Cube {
        let full = self.model_cube();
        let inputs: Vec<SatLit> = self
            .inputs
            .iter()
            .map(|&l| if self.u.value(l) { l } else { !l })
            .collect();
        let temporary = self.u.fresh();
        let mut clause: Vec<SatLit> = successor
            .iter()
            .map(|&(j, v)| if v { !self.next[j] } else { self.next[j] })
            .collect();
        clause.push(!temporary);
        self.u.add_clause(&clause);
        let state: Vec<SatLit> = full
            .iter()
            .map(|&(j, v)| if v { self.current[j] } else { !self.current[j] })
            .collect();
        let mut assumptions = vec![temporary];
        assumptions.extend(&inputs);
        assumptions.extend(&state);
        let lifted = match self.u.solve(&assumptions) {
            Some(false) => full
                .iter()
                .zip(&state)
                .filter(|(_, &l)| self.u.in_core(l))
                .map(|(&c, _)| c)
                .collect(),
            Some(true) | None => full,
        };
        self.u.add_clause(&[!temporary]);
        lifted
    }

    /// Whether F_i already excludes every state of `cube`.
    fn blocked_at(&mut self, cube: &Cube, i: usize) -> Option<bool> {
        let mut assumptions = self.frame_assumptions(i);
        assumptions.extend(
            cube.iter()
                .map(|&(j, v)| if v { self.current[j] } else { !self.current[j] }),
        );
        self.u.solve(&assumptions).map(|sat| !sat)
    }

    /// Blocks `cube` at frame `k`: `Some(length)` when it cannot be, as a
    /// counterexample of that many scans.
    fn block(&mut self, cube: Cube, k: usize) -> Result<Option<usize>, String> {
        let mut obligations = vec![Obligation { cube, to_bad: 0 }];
        let mut queue = BinaryHeap::new();
        queue.push(Reverse((k, 0usize)));
        while let Some(Reverse((frame, id))) = queue.pop() {
            let cube = obligations[id].cube.clone();
            let to_bad = obligations[id].to_bad;
            match self.blocked_at(&cube, frame) {
                None => return Err(super::bmc::timeout()),
                Some(true) => continue,
                Some(false) => {}
            }
            match self.relative(&cube, frame - 1) {
                Relative::Stopped => return Err(super::bmc::timeout()),
                Relative::Sat(predecessor) => {
                    if frame == 1 || self.meets_init(&predecessor) {
                        return Ok(Some(to_bad + 1));
                    }
                    obligations.push(Obligation {
                        cube: predecessor,
                        to_bad: to_bad + 1,
                    });
                    queue.push(Reverse((frame - 1, obligations.len() - 1)));
                    queue.push(Reverse((frame, id)));
                }
                Relative::Unsat(core) => {
                    let general = self.generalize(&cube, core, frame)?;
                    let mut at = frame;
                    while at < k {
                        match self.relative(&general, at) {
                            Relative::Stopped => return Err(super::bmc::timeout()),
                            Relative::Unsat(_) => at += 1,
                            Relative::Sat(_) => break,
                        }
                    }
                    self.add_blocked(general, at);
                }
            }
        }
        Ok(None)
    }

    /// A smaller cube blocked at `frame` as well: the unsat core's part,
    /// then literals dropped while the cube stays blocked and outside the
    /// power-up state.
    fn generalize(&mut self, cube: &Cube, core: Cube, frame: usize) -> Result<Cube, String> {
        let mut general = self.outside_init(cube, core);
        let mut i = 0;
        let mut failures = 0;
        while i < general.len() && general.len() > 1 && failures < GENERALIZE_FAILURES {
            let mut candidate = general.clone();
            candidate.remove(i);
            if self.meets_init(&candidate) {
                i += 1;
                continue;
            }
            match self.relative(&candidate, frame - 1) {
                Relative::Stopped => return Err(super::bmc::timeout()),
                Relative::Unsat(core) => {
                    general = self.outside_init(&candidate, core);
                    failures = 0;
                }
                Relative::Sat(_) => {
                    failures += 1;
                    i += 1;
                }
            }
        }
        Ok(general)
    }

    /// `part` of `cube`, with a literal of `cube` the power-up state
    /// contradicts added when `part` alone would meet it.
    fn outside_init(&self, cube: &Cube, mut part: Cube) -> Cube {
        if part.is_empty() || self.meets_init(&part) {
            if let Some(&literal) = cube.iter().find(|&&(i, v)| self.init[i] != v) {
                if !part.contains(&literal) {
                    part.push(literal);
                }
            }
        }
        part.sort_unstable();
        part
    }
}

enum Relative {
    Sat(Cube),
    Unsat(Cube),
    Stopped,
}

/// Literals `generalize` tries to drop in a row without success before it
/// settles for the cube it has.
const GENERALIZE_FAILURES: usize = usize::MAX;
