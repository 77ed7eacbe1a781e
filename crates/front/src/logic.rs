//! The logic stack of a rung, written once for the walkers that evaluate a
//! rung: the interpreter (its values are bits) and the IR lowering (its
//! values are IR values). What LD, AND, OR and the `Logic` instructions do
//! to the stack, and what a read of an empty stack gives, is decided here;
//! a walker says only how it combines two values.

use crate::program::{Contact, Logic, Op};

/// The result so far, the blocks LD opened (ANB/ORB close them) and the
/// branch points MPS saved (MRD reads them, MPP takes them).
#[derive(Clone, Debug)]
pub struct LogicStack<T> {
    pub result: T,
    blocks: Vec<T>,
    branches: Vec<T>,
}

impl<T: Copy> LogicStack<T> {
    /// An empty stack whose result is `result`.
    pub fn new(result: T) -> Self {
        LogicStack {
            result,
            blocks: Vec::new(),
            branches: Vec::new(),
        }
    }

    /// Empties the stack: at a new rung (`RungLogic::load`), and in the
    /// lowering also where a jump or a state block lands (no checked rung
    /// spans those places).
    pub fn clear(&mut self) {
        self.blocks.clear();
        self.branches.clear();
    }
}

/// How a walker evaluates a rung; the provided methods move its values
/// through the `LogicStack` it holds.
pub trait RungLogic {
    type Value: Copy;

    fn logic_stack(&mut self) -> &mut LogicStack<Self::Value>;
    fn and(&mut self, a: Self::Value, b: Self::Value) -> Self::Value;
    fn or(&mut self, a: Self::Value, b: Self::Value) -> Self::Value;
    fn not(&mut self, value: Self::Value) -> Self::Value;
    /// Whether `value` rose (`falling` false) or fell since the instruction
    /// with previous-scan slot `slot` last ran (MEP/MEF, P forms).
    fn transition(&mut self, slot: u32, value: Self::Value, falling: bool) -> Self::Value;
    /// OFF, what a read of an empty stack gives. The checker refuses a
    /// program that reads one (E0010, E0011).
    fn off(&mut self) -> Self::Value;
    /// Whether `contact` passes, evaluated (and its edge slot updated) even
    /// where no power reaches it.
    fn evaluate_contact(&mut self, contact: &Contact, line: u32) -> Self::Value;
    /// `passes` under the power rails of the master-control levels in
    /// `mc_levels` (bit k = level Nk).
    fn under_rails(&mut self, mc_levels: u8, passes: Self::Value) -> Self::Value;

    /// The power an instruction with a pulse form (CALLP, MOVP, ...) runs
    /// with: `power` itself, or with the instruction's previous-scan `slot`
    /// (the P form) the rising edge of `power`.
    fn pulsed(&mut self, slot: Option<u32>, power: Self::Value) -> Self::Value {
        match slot {
            Some(slot) => self.transition(slot, power, false),
            None => power,
        }
    }

    /// LD, AND, OR and the `Logic` instructions; the other kinds (outputs,
    /// jumps, calls, lines of their own) read the result but leave the
    /// stack to the walker.
    fn evaluate(&mut self, op: &Op, line: u32) {
        match op {
            Op::Load {
                contact,
                new_rung,
                mc_levels,
            } => self.load_contact(contact, *new_rung, *mc_levels, line),
            Op::And(contact) => self.and_contact(contact, line),
            Op::Or(contact) => self.or_contact(contact, line),
            Op::Logic(logic) => self.logic(*logic),
            Op::Output(_) | Op::Jump { .. } | Op::Call { .. } | Op::Line(_) => {}
        }
    }

    /// LD/LDI/LDP/LD=...: the contact, under its rails, starts a block or
    /// (`new_rung`) a rung.
    fn load_contact(&mut self, contact: &Contact, new_rung: bool, mc_levels: u8, line: u32) {
        let passes = self.evaluate_contact(contact, line);
        let powered = self.under_rails(mc_levels, passes);
        self.load(new_rung, powered);
    }

    /// AND-type contacts.
    fn and_contact(&mut self, contact: &Contact, line: u32) {
        let passes = self.evaluate_contact(contact, line);
        self.series(passes);
    }

    /// OR-type contacts.
    fn or_contact(&mut self, contact: &Contact, line: u32) {
        let passes = self.evaluate_contact(contact, line);
        self.parallel(passes);
    }

    /// LD: `passes` (the contact under its power rail) starts a block, or a
    /// new rung (`new_rung`), whose stack starts empty.
    fn load(&mut self, new_rung: bool, passes: Self::Value) {
        let stack = self.logic_stack();
        if new_rung {
            stack.clear();
        } else {
            stack.blocks.push(stack.result);
        }
        stack.result = passes;
    }

    /// AND: `passes` in series with the result.
    fn series(&mut self, passes: Self::Value) {
        let result = self.logic_stack().result;
        let next = self.and(result, passes);
        self.logic_stack().result = next;
    }

    /// OR: `passes` in parallel with the result.
    fn parallel(&mut self, passes: Self::Value) {
        let result = self.logic_stack().result;
        let next = self.or(result, passes);
        self.logic_stack().result = next;
    }

    /// ANB, ORB, MPS, MRD, MPP, INV, MEP/MEF.
    fn logic(&mut self, op: Logic) {
        let result = self.logic_stack().result;
        let next = match op {
            Logic::AndBlock => {
                let earlier = self.pop_block();
                self.and(earlier, result)
            }
            Logic::OrBlock => {
                let earlier = self.pop_block();
                self.or(earlier, result)
            }
            Logic::BranchPush => {
                self.logic_stack().branches.push(result);
                result
            }
            Logic::BranchRead => match self.logic_stack().branches.last() {
                Some(&saved) => saved,
                None => self.off(),
            },
            Logic::BranchPop => match self.logic_stack().branches.pop() {
                Some(saved) => saved,
                None => self.off(),
            },
            Logic::Invert => self.not(result),
            Logic::ResultEdge { falling, slot } => self.transition(slot, result, falling),
        };
        self.logic_stack().result = next;
    }

    /// The block ANB/ORB closes, OFF on an empty stack.
    fn pop_block(&mut self) -> Self::Value {
        match self.logic_stack().blocks.pop() {
            Some(earlier) => earlier,
            None => self.off(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Writes the rung as an expression, to see which values each
    /// instruction combines and in which order.
    struct Expression {
        stack: LogicStack<usize>,
        terms: Vec<String>,
    }

    impl Expression {
        fn new() -> Self {
            Expression {
                stack: LogicStack::new(0),
                terms: vec!["power".into()],
            }
        }
        fn term(&mut self, text: String) -> usize {
            self.terms.push(text);
            self.terms.len() - 1
        }
        fn named(&mut self, name: &str) -> usize {
            self.term(name.into())
        }
        fn result(&self) -> &str {
            &self.terms[self.stack.result]
        }
    }

    impl RungLogic for Expression {
        type Value = usize;
        fn logic_stack(&mut self) -> &mut LogicStack<usize> {
            &mut self.stack
        }
        fn and(&mut self, a: usize, b: usize) -> usize {
            let text = format!("({} & {})", self.terms[a], self.terms[b]);
            self.term(text)
        }
        fn or(&mut self, a: usize, b: usize) -> usize {
            let text = format!("({} | {})", self.terms[a], self.terms[b]);
            self.term(text)
        }
        fn not(&mut self, value: usize) -> usize {
            let text = format!("!{}", self.terms[value]);
            self.term(text)
        }
        fn transition(&mut self, slot: u32, value: usize, falling: bool) -> usize {
            let edge = if falling { "fall" } else { "rise" };
            let text = format!("{edge}{slot}({})", self.terms[value]);
            self.term(text)
        }
        fn off(&mut self) -> usize {
            self.term("OFF".into())
        }
        fn evaluate_contact(&mut self, contact: &Contact, _line: u32) -> usize {
            let text = match contact {
                Contact::Constant(on) => format!("{on}"),
                Contact::Level { .. } | Contact::Edge { .. } | Contact::Compare { .. } => "contact".into(),
            };
            self.term(text)
        }
        fn under_rails(&mut self, mc_levels: u8, passes: usize) -> usize {
            if mc_levels == 0 {
                return passes;
            }
            let text = format!("(N{mc_levels:b} & {})", self.terms[passes]);
            self.term(text)
        }
    }

    #[test]
    fn blocks_combine_with_the_block_before_them() {
        // LD a / LD b / OR c / ANB / LD d / ORB
        let mut rung = Expression::new();
        for (new_rung, name) in [(true, "a"), (false, "b")] {
            let value = rung.named(name);
            rung.load(new_rung, value);
        }
        let c = rung.named("c");
        rung.parallel(c);
        rung.logic(Logic::AndBlock);
        let d = rung.named("d");
        rung.load(false, d);
        rung.logic(Logic::OrBlock);
        assert_eq!(rung.result(), "((a & (b | c)) | d)");
    }

    #[test]
    fn branches_give_back_what_mps_saved() {
        // LD a / MPS / AND b / MRD / AND c / MPP / INV / MEP
        let mut rung = Expression::new();
        let a = rung.named("a");
        rung.load(true, a);
        rung.logic(Logic::BranchPush);
        let b = rung.named("b");
        rung.series(b);
        assert_eq!(rung.result(), "(a & b)");
        rung.logic(Logic::BranchRead);
        let c = rung.named("c");
        rung.series(c);
        assert_eq!(rung.result(), "(a & c)");
        rung.logic(Logic::BranchPop);
        rung.logic(Logic::Invert);
        rung.logic(Logic::ResultEdge {
            falling: false,
            slot: 3,
        });
        assert_eq!(rung.result(), "rise3(!a)");
        // The stack is empty again: a further MPP reads OFF.
        rung.logic(Logic::BranchPop);
        assert_eq!(rung.result(), "OFF");
    }

    #[test]
    fn an_empty_stack_reads_off() {
        let cases = [
            (Logic::AndBlock, "(OFF & a)"),
            (Logic::OrBlock, "(OFF | a)"),
            (Logic::BranchRead, "OFF"),
            (Logic::BranchPop, "OFF"),
        ];
        for (op, expected) in cases {
            let mut rung = Expression::new();
            let a = rung.named("a");
            rung.load(true, a);
            rung.logic(op);
            assert_eq!(rung.result(), expected, "{op:?}");
        }
    }

    #[test]
    fn a_new_rung_starts_with_an_empty_stack() {
        // LD a / MPS / LD b (a block) / LD c (a new rung) / MRD / ORB
        let mut rung = Expression::new();
        let a = rung.named("a");
        rung.load(true, a);
        rung.logic(Logic::BranchPush);
        let b = rung.named("b");
        rung.load(false, b);
        let c = rung.named("c");
        rung.load(true, c);
        rung.logic(Logic::BranchRead);
        rung.logic(Logic::OrBlock);
        assert_eq!(rung.result(), "(OFF | OFF)");
    }

    #[test]
    fn contacts_are_evaluated_then_put_under_their_rails() {
        let mut rung = Expression::new();
        rung.load_contact(&Contact::Constant(true), true, 0b101, 1);
        rung.and_contact(&Contact::Constant(false), 2);
        rung.or_contact(&Contact::Constant(true), 3);
        assert_eq!(rung.result(), "(((N101 & true) & false) | true)");
    }

    #[test]
    fn only_rung_logic_moves_the_stack_and_a_pulse_form_takes_the_rising_edge() {
        let mut rung = Expression::new();
        let load = Op::Load {
            contact: Contact::Constant(true),
            new_rung: true,
            mc_levels: 0,
        };
        rung.evaluate(&load, 1);
        rung.evaluate(&Op::Logic(Logic::Invert), 2);
        rung.evaluate(&Op::Line(crate::program::Line::MainEnd), 3);
        rung.evaluate(&Op::Jump { target: 0, label: 0 }, 4);
        assert_eq!(rung.result(), "!true");
        let power = rung.stack.result;
        let pulsed = rung.pulsed(Some(4), power);
        assert_eq!(rung.terms[pulsed], "rise4(!true)");
        assert_eq!(rung.pulsed(None, power), power);
    }
}
