//! And-inverter graphs: the bit-level form of one scan that the SAT-based
//! engines unroll and `--emit aiger` writes. A literal is a node number
//! times two, plus one when negated; node 0 is the constant FALSE. AND
//! nodes are hashed structurally and folded with constants, so building
//! the same gate twice gives the same literal.

use rustc_hash::FxHashMap;

/// A literal: `2 * node + negated`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Lit(pub u32);

impl Lit {
    pub const FALSE: Lit = Lit(0);
    pub const TRUE: Lit = Lit(1);

    pub fn node(self) -> u32 {
        self.0 >> 1
    }

    pub fn negated(self) -> bool {
        self.0 & 1 == 1
    }

    pub fn constant(value: bool) -> Lit {
        if value {
            Lit::TRUE
        } else {
            Lit::FALSE
        }
    }
}

impl std::ops::Not for Lit {
    type Output = Lit;
    fn not(self) -> Lit {
        Lit(self.0 ^ 1)
    }
}

/// A node of the graph.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Node {
    False,
    /// Free input number `n` (chosen anew each scan).
    Input(u32),
    /// Latch number `n` (its value in the current state).
    Latch(u32),
    And(Lit, Lit),
}

/// A state bit: its value in the initial state and its value in the next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Latch {
    pub node: u32,
    pub init: bool,
    pub next: Lit,
}

#[derive(Clone, Debug)]
pub struct Aig {
    pub nodes: Vec<Node>,
    hashed: FxHashMap<(Lit, Lit), Lit>,
    /// Node of each input, by input number.
    pub inputs: Vec<u32>,
    pub latches: Vec<Latch>,
}

impl Default for Aig {
    fn default() -> Aig {
        Aig::new()
    }
}

impl Aig {
    pub fn new() -> Aig {
        Aig {
            nodes: vec![Node::False],
            hashed: FxHashMap::default(),
            inputs: Vec::new(),
            latches: Vec::new(),
        }
    }

    pub fn input(&mut self) -> Lit {
        let node = self.nodes.len() as u32;
        self.nodes.push(Node::Input(self.inputs.len() as u32));
        self.inputs.push(node);
        Lit(node * 2)
    }

    /// A latch with `init`; its next value is set later (`set_next`),
    /// until then it keeps its value.
    pub fn latch(&mut self, init: bool) -> Lit {
        let node = self.nodes.len() as u32;
        self.nodes.push(Node::Latch(self.latches.len() as u32));
        self.latches.push(Latch {
            node,
            init,
            next: Lit(node * 2),
        });
        Lit(node * 2)
    }

    /// Sets the next value of the latch whose current value is `latch`.
    pub fn set_next(&mut self, latch: Lit, next: Lit) {
        if let Some(Node::Latch(n)) = self.nodes.get(latch.node() as usize) {
            self.latches[*n as usize].next = next;
        }
    }

    pub fn and(&mut self, a: Lit, b: Lit) -> Lit {
        if a == Lit::FALSE || b == Lit::FALSE || a == !b {
            return Lit::FALSE;
        }
        if a == Lit::TRUE || a == b {
            return b;
        }
        if b == Lit::TRUE {
            return a;
        }
        // ¬(x ∧ y) ∧ ¬(x ∧ ¬y) is ¬x: the two halves of a branch joined
        // again (a block after an if-else) fold back to its guard.
        if let (true, true, Some(Node::And(a1, a2)), Some(Node::And(b1, b2))) = (
            a.negated(),
            b.negated(),
            self.nodes.get(a.node() as usize).copied(),
            self.nodes.get(b.node() as usize).copied(),
        ) {
            for (x, y) in [(a1, a2), (a2, a1)] {
                if (b1 == x && b2 == !y) || (b2 == x && b1 == !y) {
                    return !x;
                }
            }
        }
        let key = if a < b { (a, b) } else { (b, a) };
        if let Some(&lit) = self.hashed.get(&key) {
            return lit;
        }
        let node = self.nodes.len() as u32;
        self.nodes.push(Node::And(key.0, key.1));
        self.hashed.insert(key, Lit(node * 2));
        Lit(node * 2)
    }

    pub fn or(&mut self, a: Lit, b: Lit) -> Lit {
        !self.and(!a, !b)
    }

    pub fn xor(&mut self, a: Lit, b: Lit) -> Lit {
        let one = self.and(a, !b);
        let other = self.and(!a, b);
        self.or(one, other)
    }

    pub fn iff(&mut self, a: Lit, b: Lit) -> Lit {
        !self.xor(a, b)
    }

    pub fn implies(&mut self, a: Lit, b: Lit) -> Lit {
        self.or(!a, b)
    }

    /// `condition ? if_true : if_false`.
    pub fn mux(&mut self, condition: Lit, if_true: Lit, if_false: Lit) -> Lit {
        if condition == Lit::TRUE || if_true == if_false {
            return if_true;
        }
        if condition == Lit::FALSE {
            return if_false;
        }
        let t = self.and(condition, if_true);
        let f = self.and(!condition, if_false);
        self.or(t, f)
    }

    pub fn and_all(&mut self, lits: impl IntoIterator<Item = Lit>) -> Lit {
        lits.into_iter().fold(Lit::TRUE, |acc, l| self.and(acc, l))
    }

    pub fn or_all(&mut self, lits: impl IntoIterator<Item = Lit>) -> Lit {
        lits.into_iter().fold(Lit::FALSE, |acc, l| self.or(acc, l))
    }

    /// The nodes `roots` depend on through AND gates and latches' next
    /// values (the cone of influence), as a mark per node.
    pub fn cone(&self, roots: &[Lit]) -> Vec<bool> {
        let mut marked = vec![false; self.nodes.len()];
        let mut stack: Vec<u32> = roots.iter().map(|l| l.node()).collect();
        while let Some(node) = stack.pop() {
            let Some(mark) = marked.get_mut(node as usize) else {
                continue;
            };
            if *mark {
                continue;
            }
            *mark = true;
            match self.nodes[node as usize] {
                Node::False | Node::Input(_) => {}
                Node::Latch(n) => stack.push(self.latches[n as usize].next.node()),
                Node::And(a, b) => {
                    stack.push(a.node());
                    stack.push(b.node());
                }
            }
        }
        marked
    }

    /// Values of every node, given the inputs' and latches' values.
    pub fn simulate(&self, inputs: &[bool], latches: &[bool]) -> Vec<bool> {
        let mut values = vec![false; self.nodes.len()];
        for (n, node) in self.nodes.iter().enumerate() {
            values[n] = match *node {
                Node::False => false,
                Node::Input(i) => inputs.get(i as usize).copied().unwrap_or(false),
                Node::Latch(l) => latches.get(l as usize).copied().unwrap_or(false),
                Node::And(a, b) => value_of(&values, a) && value_of(&values, b),
            };
        }
        values
    }
}

/// A literal's value among simulated node values.
pub fn value_of(values: &[bool], lit: Lit) -> bool {
    values.get(lit.node() as usize).copied().unwrap_or(false) != lit.negated()
}

impl Aig {
    /// The same graph with every latch that never changes replaced by its
    /// value (a latch whose next value is itself, or the constant it
    /// starts with), until none is left: the devices a scan reads but
    /// never writes, the validity latch without assumptions. Returns the
    /// new graph and each old node's literal in it.
    pub fn without_constant_latches(&self) -> (Aig, Vec<Lit>) {
        let mut current = self.clone();
        let mut total: Vec<Lit> = (0..self.nodes.len() as u32).map(|n| Lit(2 * n)).collect();
        loop {
            let constant: Vec<Option<bool>> = current
                .latches
                .iter()
                .map(|l| {
                    let own = Lit(2 * l.node);
                    (l.next == own || l.next == Lit::constant(l.init)).then_some(l.init)
                })
                .collect();
            if constant.iter().all(Option::is_none) {
                return (current, total);
            }
            let (next, map) = current.rebuild(&constant);
            total = total
                .into_iter()
                .map(|l| {
                    let m = map[l.node() as usize];
                    if l.negated() {
                        !m
                    } else {
                        m
                    }
                })
                .collect();
            current = next;
        }
    }

    /// A copy with the latches `constant` names replaced by constants.
    fn rebuild(&self, constant: &[Option<bool>]) -> (Aig, Vec<Lit>) {
        let mut new = Aig::new();
        let mut map = vec![Lit::FALSE; self.nodes.len()];
        let translate = |map: &[Lit], l: Lit| {
            let m = map[l.node() as usize];
            if l.negated() {
                !m
            } else {
                m
            }
        };
        for (n, node) in self.nodes.iter().enumerate() {
            map[n] = match *node {
                Node::False => Lit::FALSE,
                Node::Input(_) => new.input(),
                Node::Latch(l) => match constant.get(l as usize).copied().flatten() {
                    Some(value) => Lit::constant(value),
                    None => new.latch(self.latches[l as usize].init),
                },
                Node::And(a, b) => {
                    let (a, b) = (translate(&map, a), translate(&map, b));
                    new.and(a, b)
                }
            };
        }
        for latch in &self.latches {
            let lit = map[latch.node as usize];
            if let Some(Node::Latch(_)) = new.nodes.get(lit.node() as usize) {
                let next = translate(&map, latch.next);
                new.set_next(lit, next);
            }
        }
        (new, map)
    }
}
