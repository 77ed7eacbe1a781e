//! The AIG in a SAT solver (batsat: MiniSat's algorithm in Rust, MIT, with
//! assumptions and their unsat cores, which BMC, k-induction and IC3 need;
//! docs/verify.md says why this one). Each frame is one copy of the scan;
//! an AND gate becomes three clauses (Tseitin), and only the gates a query
//! reaches are encoded.

use super::aig::{self, Aig, Node};
use batsat::{lbool, Callbacks, SolverInterface, SolverOpts};
use rustc_hash::FxHashMap;
use std::time::Instant;

pub use batsat::Lit as SatLit;

/// Stops the solver at a deadline (the `--timeout`).
pub struct Deadline(pub Instant);

impl Callbacks for Deadline {
    fn stop(&self) -> bool {
        Instant::now() >= self.0
    }
}

pub type Solver = batsat::Solver<Deadline>;

/// A fresh solver that stops at `deadline`.
pub fn solver(deadline: Instant) -> Solver {
    batsat::Solver::new(SolverOpts::default(), Deadline(deadline))
}

/// Copies of the AIG, frame after frame: a latch in frame `f + 1` is its
/// next value in frame `f`; in frame 0 it is its initial value
/// (`initialized`) or free (induction, IC3).
pub struct Unroller<'a> {
    pub aig: &'a Aig,
    pub solver: Solver,
    frames: Vec<FxHashMap<u32, SatLit>>,
    truth: SatLit,
    initialized: bool,
}

impl<'a> Unroller<'a> {
    pub fn new(aig: &'a Aig, deadline: Instant, initialized: bool) -> Unroller<'a> {
        let mut solver = solver(deadline);
        let truth = SatLit::new(solver.new_var_default(), true);
        solver.add_clause_reuse(&mut vec![truth]);
        Unroller {
            aig,
            solver,
            frames: Vec::new(),
            truth,
            initialized,
        }
    }

    pub fn fresh(&mut self) -> SatLit {
        SatLit::new(self.solver.new_var_default(), true)
    }

    pub fn add_clause(&mut self, clause: &[SatLit]) {
        let mut clause = clause.to_vec();
        self.solver.add_clause_reuse(&mut clause);
    }

    /// `lit` in frame `frame`.
    pub fn lit(&mut self, frame: usize, lit: aig::Lit) -> SatLit {
        let node = self.node(frame, lit.node());
        if lit.negated() {
            !node
        } else {
            node
        }
    }

    fn known(&self, frame: usize, node: u32) -> Option<SatLit> {
        self.frames.get(frame).and_then(|f| f.get(&node)).copied()
    }

    fn node(&mut self, frame: usize, node: u32) -> SatLit {
        while self.frames.len() <= frame {
            self.frames.push(FxHashMap::default());
        }
        if let Some(l) = self.known(frame, node) {
            return l;
        }
        // Depth-first without recursion: the gates of a scan are deep.
        let mut stack = vec![(frame, node)];
        while let Some(&(f, n)) = stack.last() {
            if self.known(f, n).is_some() {
                stack.pop();
                continue;
            }
            let encoded = match self.aig.nodes[n as usize] {
                Node::False => Some(!self.truth),
                Node::Input(_) => Some(self.fresh()),
                Node::Latch(l) => {
                    let latch = self.aig.latches[l as usize];
                    if f == 0 {
                        Some(if self.initialized {
                            if latch.init {
                                self.truth
                            } else {
                                !self.truth
                            }
                        } else {
                            self.fresh()
                        })
                    } else {
                        match self.known(f - 1, latch.next.node()) {
                            Some(l) => Some(if latch.next.negated() { !l } else { l }),
                            None => {
                                stack.push((f - 1, latch.next.node()));
                                None
                            }
                        }
                    }
                }
                Node::And(a, b) => match (self.known(f, a.node()), self.known(f, b.node())) {
                    (Some(x), Some(y)) => {
                        let x = if a.negated() { !x } else { x };
                        let y = if b.negated() { !y } else { y };
                        let v = self.fresh();
                        self.solver.add_clause_reuse(&mut vec![!v, x]);
                        self.solver.add_clause_reuse(&mut vec![!v, y]);
                        self.solver.add_clause_reuse(&mut vec![v, !x, !y]);
                        Some(v)
                    }
                    (x, y) => {
                        if x.is_none() {
                            stack.push((f, a.node()));
                        }
                        if y.is_none() {
                            stack.push((f, b.node()));
                        }
                        None
                    }
                },
            };
            if let Some(l) = encoded {
                self.frames[f].insert(n, l);
                stack.pop();
            }
        }
        self.known(frame, node).unwrap_or(self.truth)
    }

    /// `Some(true)`: satisfiable; `None`: stopped at the deadline.
    pub fn solve(&mut self, assumptions: &[SatLit]) -> Option<bool> {
        solve(&mut self.solver, assumptions)
    }

    /// The literals of the free inputs encoded in `frame`.
    pub fn encoded_inputs(&self, frame: usize) -> Vec<SatLit> {
        let Some(f) = self.frames.get(frame) else {
            return Vec::new();
        };
        let mut inputs: Vec<(u32, SatLit)> = f
            .iter()
            .filter(|(&n, _)| matches!(self.aig.nodes[n as usize], Node::Input(_)))
            .map(|(&n, &l)| (n, l))
            .collect();
        inputs.sort_unstable_by_key(|&(n, _)| n);
        inputs.into_iter().map(|(_, l)| l).collect()
    }

    /// Whether an assumption is in the last unsat core.
    pub fn in_core(&self, assumption: SatLit) -> bool {
        self.solver.unsat_core_contains_var(assumption.var())
    }

    /// A literal's value in the last model.
    pub fn value(&self, lit: SatLit) -> bool {
        self.solver.value_lit(lit) == lbool::TRUE
    }

    /// A word's value in frame `frame` of the last model, as an unsigned
    /// number (its bits must have been encoded).
    pub fn word_value(&mut self, frame: usize, word: &[aig::Lit]) -> u64 {
        let mut value = 0u64;
        for (i, &bit) in word.iter().enumerate() {
            let l = self.lit(frame, bit);
            if self.value(l) && i < 64 {
                value |= 1 << i;
            }
        }
        value
    }
}

/// Solves under assumptions: `None` when stopped.
pub fn solve(solver: &mut Solver, assumptions: &[SatLit]) -> Option<bool> {
    let result = solver.solve_limited(assumptions);
    if result == lbool::TRUE {
        Some(true)
    } else if result == lbool::FALSE {
        Some(false)
    } else {
        None
    }
}
