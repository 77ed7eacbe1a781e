//! The ladder read back as IL: contacts from the tree (LD, AND, OR, with
//! ANB/ORB for blocks), MPS/MRD/MPP for splits, outputs and lines of their
//! own. Compiled again, it gives the same checked program (what runs); the
//! property test of `compiler/tests/commands/ladder.rs` holds the builder to that.

use super::names::instruction;
use super::{Body, Element, Ladder, Node, Tail, TailItem};
use ladder_front::isa::Role;
use ladder_front::program::{CheckedProgram, Line, Op};

/// The IL of a ladder built from `program`.
pub fn to_il(ladder: &Ladder, program: &CheckedProgram) -> String {
    let mut out = Writer {
        program,
        text: String::new(),
    };
    for rung in &ladder.rungs {
        for comment in &rung.comments {
            out.text.push_str(&format!("// {comment}\n"));
        }
        match &rung.body {
            Body::Logic { condition, tail } => {
                out.node(condition, Role::Load);
                out.tail(tail);
            }
            Body::StepEnd { fx_return, .. } => out.line(if *fx_return { "RET" } else { "STLE" }),
            Body::Step { element, .. }
            | Body::Label { element, .. }
            | Body::MasterControlReset { element, .. }
            | Body::Rail { element } => out.element(element, Role::Load),
        }
    }
    out.line("END");
    // A CJ may name a label after END (it then jumps to the end of the
    // program): the label is written there again.
    let defined: Vec<u32> = program
        .instructions
        .iter()
        .filter_map(|i| {
            if let Op::Line(Line::Label { number }) = i.op {
                Some(number)
            } else {
                None
            }
        })
        .collect();
    let mut after_end: Vec<u32> = program
        .instructions
        .iter()
        .filter_map(|i| {
            if let Op::Jump { label, .. } = i.op {
                Some(label)
            } else {
                None
            }
        })
        .filter(|label| !defined.contains(label))
        .collect();
    after_end.sort_unstable();
    after_end.dedup();
    for label in after_end {
        out.line(&format!("P{label}"));
    }
    out.text
}

struct Writer<'p> {
    program: &'p CheckedProgram,
    text: String,
}

impl Writer<'_> {
    fn line(&mut self, text: &str) {
        self.text.push_str(text);
        self.text.push('\n');
    }

    fn element(&mut self, element: &Element, role: Role) {
        let (mnemonic, operands) = instruction(self.program, element.index, role);
        let mut line = mnemonic;
        for operand in operands {
            line.push(' ');
            line.push_str(&operand);
        }
        self.line(&line);
    }

    /// A network in `role`: the first part takes the role, the rest joins
    /// in series (AND, or a block and ANB) or in parallel (OR, or a block
    /// and ORB).
    fn node(&mut self, node: &Node, role: Role) {
        match node {
            Node::Element(element) => self.element(element, role),
            Node::Power => {}
            Node::Block(inner) => self.node(inner, role),
            Node::Series(nodes) | Node::Parallel(nodes) => {
                let (joined, block) = match node {
                    Node::Series(_) => (Role::And, "ANB"),
                    Node::Element(_) | Node::Power | Node::Block(_) | Node::Parallel(_) => (Role::Or, "ORB"),
                };
                let mut nodes = nodes.iter();
                if let Some(first) = nodes.next() {
                    self.node(first, role);
                }
                for next in nodes {
                    match next {
                        Node::Block(inner) => {
                            self.node(inner, Role::Load);
                            self.line(block);
                        }
                        Node::Element(_) | Node::Power | Node::Series(_) | Node::Parallel(_) => self.node(next, joined),
                    }
                }
            }
        }
    }

    fn tail(&mut self, tail: &Tail) {
        for item in &tail.items {
            match item {
                TailItem::Contacts(node) => self.node(node, Role::Load),
                TailItem::Output(element) => self.element(element, Role::Load),
                TailItem::Split(branches) => {
                    self.line("MPS");
                    let last = branches.len().saturating_sub(1);
                    for (number, branch) in branches.iter().enumerate() {
                        if number == last {
                            self.line("MPP");
                        } else if number > 0 {
                            self.line("MRD");
                        }
                        self.tail(branch);
                    }
                }
            }
        }
    }
}
