//! The ladder diagram of a checked program: what `ladderc render` draws,
//! what the monitor of `ladderc serve` shows live, and what the HTML test
//! reports show at a failing scan.
//!
//! Like the interpreter, it is built from the checked program (not from the
//! IR): every rung is the tree the logic stack of its instructions builds —
//! contacts in series and in parallel, blocks joined by ANB/ORB, MPS/MRD/MPP
//! splits into output branches — with every element keeping its instruction
//! (its source span, line and step). Structure that is not a rung (STL
//! steps, labels, MCR, FOR/NEXT, FEND, SRET) is a rung of its own, as GX
//! Works2 draws it. Comments of the source (comment lines of IL, line
//! statements of an export) become rung comments; device comments (the
//! `//@ comment` lines a GX Developer project's listing carries) are drawn
//! under the contacts and coils of their devices.
//!
//! The tree keeps how each block was joined (`AND c` or `LD c ... ANB`), so
//! that `to_il` gives back a program that compiles to the same checked
//! program: the property test of `compiler/tests/commands/ladder.rs` checks it on
//! every scenario program and on random ones.

mod build;
mod il;
pub mod layout;
pub mod monitor;
mod names;
pub mod svg;
mod wrap;

pub use build::build;
pub use il::to_il;
pub use names::{bit_name, word_name};

use ladder_front::program::Instruction;
use ladder_front::source::Span;

/// A program as a ladder diagram.
#[derive(Clone, Debug, PartialEq)]
pub struct Ladder {
    pub name: String,
    pub rungs: Vec<Rung>,
}

/// Device comments (`//@ comment` lines of the source, a GX Developer
/// project's COMMENT.wcd), keyed by the device's name as drawn (`X000`).
pub type DeviceComments = std::sync::Arc<std::collections::BTreeMap<String, String>>;

/// One rung: contacts and outputs, or a structural line.
#[derive(Clone, Debug, PartialEq)]
pub struct Rung {
    /// The FX step number of its first instruction: from the export or the
    /// listing when it has them, else counted as an FX CPU counts steps.
    pub step: u32,
    /// The source line of its first instruction.
    pub line: u32,
    /// Comment lines before it (IL comments, an export's line statements).
    pub comments: Vec<String>,
    /// Inside the STL block of this state.
    pub state: Option<u32>,
    /// Under the master-control levels of this mask (bit k: Nk).
    pub mc_levels: u8,
    pub body: Body,
    /// The program's device comments, drawn under contacts and coils.
    pub device_comments: DeviceComments,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Body {
    /// Contacts from the left rail, then what they drive.
    Logic { condition: Node, tail: Tail },
    /// `STL Sn`: the start of a step.
    Step { state: u32, element: Element },
    /// STLE or RET: the end of the step ladder (`fx_return`: written RET).
    StepEnd { fx_return: bool, element: Element },
    /// A jump target or subroutine entry `Pn`.
    Label { number: u32, element: Element },
    /// `MCR Nk`.
    MasterControlReset { level: u8, element: Element },
    /// `FOR n`, `NEXT`, `FEND`, `SRET`: instructions on the rail.
    Rail { element: Element },
}

/// A network of contacts.
#[derive(Clone, Debug, PartialEq)]
pub enum Node {
    Element(Element),
    /// The power the tail of a rung starts from (after an output, MPS, ...):
    /// nothing is drawn for it.
    Power,
    /// In series, in order.
    Series(Vec<Node>),
    /// In parallel, top to bottom.
    Parallel(Vec<Node>),
    /// A block started by its own LD-type contact and joined by ANB or ORB
    /// (drawn like any other branch; kept to give back the same program).
    Block(Box<Node>),
}

/// What the power drives, in order of execution.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Tail {
    pub items: Vec<TailItem>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum TailItem {
    /// More contacts on the way (after an output: `OUT Y0 / AND X1 / OUT Y1`).
    Contacts(Node),
    /// An output: a coil, SET/RST, an instruction box, CJ, CALL.
    Output(Element),
    /// MPS ... MRD ... MPP: branches from this point; the last runs to the
    /// end of the tail.
    Split(Vec<Tail>),
}

/// One instruction of the program in the diagram.
#[derive(Clone, Debug, PartialEq)]
pub struct Element {
    /// Index in the checked program's instructions.
    pub index: usize,
    pub span: Span,
    pub line: u32,
    pub step: u32,
    /// The comment after the instruction on its source line.
    pub note: Option<String>,
}

impl Element {
    /// The checked instruction it stands for.
    pub fn instruction<'p>(&self, program: &'p ladder_front::program::CheckedProgram) -> &'p Instruction {
        &program.instructions[self.index]
    }
}

impl Node {
    /// Every element of the network, left to right, top to bottom.
    pub fn elements(&self) -> Vec<&Element> {
        let mut out = Vec::new();
        self.collect(&mut out);
        out
    }

    fn collect<'a>(&'a self, out: &mut Vec<&'a Element>) {
        match self {
            Node::Element(element) => out.push(element),
            Node::Power => {}
            Node::Series(nodes) | Node::Parallel(nodes) => nodes.iter().for_each(|n| n.collect(out)),
            Node::Block(inner) => inner.collect(out),
        }
    }
}

impl Rung {
    /// Every element of the rung (contacts and outputs), in order.
    pub fn elements(&self) -> Vec<&Element> {
        fn walk<'a>(tail: &'a Tail, out: &mut Vec<&'a Element>) {
            for item in &tail.items {
                match item {
                    TailItem::Contacts(node) => node.collect(out),
                    TailItem::Output(element) => out.push(element),
                    TailItem::Split(branches) => branches.iter().for_each(|b| walk(b, out)),
                }
            }
        }
        let mut out = Vec::new();
        match &self.body {
            Body::Logic { condition, tail: t } => {
                condition.collect(&mut out);
                walk(t, &mut out);
            }
            Body::Step { element, .. }
            | Body::StepEnd { element, .. }
            | Body::Label { element, .. }
            | Body::MasterControlReset { element, .. }
            | Body::Rail { element } => out.push(element),
        }
        out
    }
}
