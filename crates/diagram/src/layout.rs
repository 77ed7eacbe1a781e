//! Where each part of a rung goes on a grid, as a ladder editor draws it:
//! contacts left to right from the left rail, parallel branches below one
//! another, outputs against the right rail, one row per output. The grid
//! is in cells (one contact wide, one row high); wires run along cell edges.
//!
//! Layout knows nothing of pixels or of values: `svg` draws it, and the
//! monitor colours what it drew by the element each cell stands for.

use super::names::{bit_name, instruction, word_name};
use super::{Body, Element, Node, Rung, Tail, TailItem};
use ladder_front::isa::Role;
use ladder_front::program::{CheckedProgram, Contact, Logic, Op, Output};

/// Columns from rail to rail, as GX Works2 shows them (eleven contacts and
/// the output); a rung that needs more is wrapped onto bands below.
pub const DEFAULT_COLUMNS: u32 = 12;

/// One rung on the grid.
#[derive(Clone, Debug, PartialEq)]
pub struct RungLayout {
    /// Width in cells: the right rail is at this column edge.
    pub columns: u32,
    pub rows: u32,
    pub cells: Vec<Cell>,
    pub wires: Vec<Wire>,
    /// A jump target (`P0`), drawn in the margin left of the rail.
    pub label: Option<String>,
    /// Where a wrapped rung goes on in the band below.
    pub connectors: Vec<Connector>,
}

/// A continuation mark of a wrapped rung: the wire that leaves one band at
/// the mark `number` (`outgoing`) comes back at the start of the next band
/// at the mark with the same number. The mark takes one cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Connector {
    pub column: u32,
    pub row: u32,
    pub number: u32,
    pub outgoing: bool,
}

/// One element of the program in its place.
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    pub column: u32,
    pub row: u32,
    /// In cells.
    pub width: u32,
    pub element: Element,
    pub symbol: Symbol,
}

/// What a cell shows.
#[derive(Clone, Debug, PartialEq)]
pub enum Symbol {
    /// `-| |-` (`kind`: open, closed, rising, falling) with the device's
    /// name above it.
    Contact { kind: ContactKind, device: String },
    /// `LD= S1 S2` and friends: the comparison in a contact box.
    Compare {
        operator: String,
        left: String,
        right: String,
    },
    /// ATI (always closed) and AFI (always open).
    Constant(bool),
    /// INV: a slash across the wire.
    Invert,
    /// MEP / MEF: an arrow on the wire.
    ResultEdge { falling: bool },
    /// `-( )-` on a device; a timer's or counter's preset below it.
    Coil { device: String, preset: Option<String> },
    /// `-[MNEMONIC operands]-`: SET, RST, PLS, application instructions,
    /// CJ, CALL, MC and the lines of their own (STL, RET, FEND, ...).
    Box { mnemonic: String, operands: Vec<String> },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactKind {
    Open,
    Closed,
    Rising,
    Falling,
}

/// A wire along cell edges: `Horizontal` on the middle of `row` from column
/// edge `from` to `to`; `Vertical` on column edge `column` from the middle
/// of row `from` to the middle of row `to`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wire {
    Horizontal { row: u32, from: u32, to: u32 },
    Vertical { column: u32, from: u32, to: u32 },
}

/// The layout of `rung` of a ladder built from `program`.
pub fn layout(rung: &Rung, program: &CheckedProgram) -> RungLayout {
    let mut grid = Grid {
        program,
        cells: Vec::new(),
        wires: Vec::new(),
        outputs: Vec::new(),
        bottom: 1,
    };
    let mut label = None;
    match &rung.body {
        Body::Logic { condition, tail } => {
            let (width, height) = size(condition, program);
            grid.node(condition, 0, 0, width);
            grid.bottom = grid.bottom.max(height);
            grid.tail(tail, width, 0);
        }
        Body::Label { number, .. } => label = Some(format!("P{number}")),
        Body::StepEnd {
            fx_return: false,
            element,
        } => {
            // The checked program keeps one end of a step ladder; the
            // source wrote it STLE.
            grid.output(element, 0, 0);
            if let Some(Cell {
                symbol: Symbol::Box { mnemonic, .. },
                ..
            }) = grid.cells.last_mut()
            {
                *mnemonic = "STLE".to_string();
            }
        }
        // Lines of their own are boxes against the right rail, fed from the
        // left one.
        Body::Step { element, .. }
        | Body::StepEnd { element, .. }
        | Body::MasterControlReset { element, .. }
        | Body::Rail { element } => grid.output(element, 0, 0),
    }
    let need = grid.outputs.iter().map(|o| o.from + o.width).max().unwrap_or(0);
    let columns = need.max(DEFAULT_COLUMNS);
    // The outputs move against the right rail; their wires reach them.
    for output in &grid.outputs {
        let at = columns - output.width;
        grid.cells[output.cell].column = at;
        if at > output.from {
            grid.wires.push(Wire::Horizontal {
                row: grid.cells[output.cell].row,
                from: output.from,
                to: at,
            });
        }
    }
    let laid = RungLayout {
        columns,
        rows: grid.bottom,
        cells: grid.cells,
        wires: grid.wires,
        label,
        connectors: Vec::new(),
    };
    super::wrap::wrap(laid, DEFAULT_COLUMNS)
}

/// An output cell placed provisionally: fed at column edge `from`.
struct PendingOutput {
    cell: usize,
    from: u32,
    width: u32,
}

struct Grid<'p> {
    program: &'p CheckedProgram,
    cells: Vec<Cell>,
    wires: Vec<Wire>,
    outputs: Vec<PendingOutput>,
    /// The first row nothing is placed on yet.
    bottom: u32,
}

/// Width and height of a network in cells.
fn size(node: &Node, program: &CheckedProgram) -> (u32, u32) {
    match node {
        Node::Element(element) => (symbol(element, program).1, 1),
        Node::Power => (0, 1),
        Node::Series(nodes) => nodes
            .iter()
            .map(|n| size(n, program))
            .fold((0, 1), |(w, h), (nw, nh)| (w + nw, h.max(nh))),
        Node::Parallel(nodes) => nodes
            .iter()
            .map(|n| size(n, program))
            .fold((0, 0), |(w, h), (nw, nh)| (w.max(nw), h + nh)),
        Node::Block(inner) => size(inner, program),
    }
}

impl Grid<'_> {
    fn horizontal(&mut self, row: u32, from: u32, to: u32) {
        if to > from {
            self.wires.push(Wire::Horizontal { row, from, to });
        }
    }

    fn vertical(&mut self, column: u32, from: u32, to: u32) {
        if to > from {
            self.wires.push(Wire::Vertical { column, from, to });
        }
    }

    /// Places `node` with its top left at (`column`, `row`), `width` cells
    /// wide: a shorter network is wired through to its right edge.
    fn node(&mut self, node: &Node, column: u32, row: u32, width: u32) {
        match node {
            Node::Element(element) => {
                let (symbol, cells) = symbol(element, self.program);
                self.cells.push(Cell {
                    column,
                    row,
                    width: cells,
                    element: element.clone(),
                    symbol,
                });
                self.horizontal(row, column + cells, column + width);
            }
            Node::Power => self.horizontal(row, column, column + width),
            Node::Block(inner) => self.node(inner, column, row, width),
            Node::Series(nodes) => {
                let mut at = column;
                for part in nodes {
                    let (w, _) = size(part, self.program);
                    self.node(part, at, row, w);
                    at += w;
                }
                self.horizontal(row, at, column + width);
            }
            Node::Parallel(nodes) => {
                let mut at = row;
                let mut last = row;
                for branch in nodes {
                    let (_, h) = size(branch, self.program);
                    self.node(branch, column, at, width);
                    last = at;
                    at += h;
                }
                self.vertical(column, row, last);
                self.vertical(column + width, row, last);
            }
        }
    }

    /// Places what the power at (`column`, `row`) drives.
    fn tail(&mut self, tail: &Tail, column: u32, row: u32) {
        let (mut column, mut row) = (column, row);
        // An output ends its row: what follows starts on a new one, fed by
        // a vertical wire from the power point.
        let mut row_taken = false;
        for item in &tail.items {
            match item {
                TailItem::Contacts(node) => {
                    if row_taken {
                        row = self.new_row(column, row);
                        row_taken = false;
                    }
                    let (w, h) = size(node, self.program);
                    self.node(node, column, row, w);
                    self.bottom = self.bottom.max(row + h);
                    column += w;
                }
                TailItem::Output(element) => {
                    if row_taken {
                        row = self.new_row(column, row);
                    }
                    self.output(element, column, row);
                    row_taken = true;
                }
                TailItem::Split(branches) => {
                    for branch in branches {
                        if row_taken {
                            row = self.new_row(column, row);
                        }
                        self.tail(branch, column, row);
                        row_taken = true;
                    }
                }
            }
        }
    }

    /// The first free row, wired down from the power point.
    fn new_row(&mut self, column: u32, row: u32) -> u32 {
        let below = self.bottom;
        self.vertical(column, row, below);
        self.bottom = below + 1;
        below
    }

    fn output(&mut self, element: &Element, from: u32, row: u32) {
        let (symbol, width) = symbol(element, self.program);
        self.outputs.push(PendingOutput {
            cell: self.cells.len(),
            from,
            width,
        });
        self.cells.push(Cell {
            column: from,
            row,
            width,
            element: element.clone(),
            symbol,
        });
        self.bottom = self.bottom.max(row + 1);
    }
}

/// What `element` shows and how many cells it takes.
pub fn symbol(element: &Element, program: &CheckedProgram) -> (Symbol, u32) {
    let Some(instruction) = program.instructions.get(element.index) else {
        return (
            Symbol::Box {
                mnemonic: String::new(),
                operands: Vec::new(),
            },
            1,
        );
    };
    let boxed = || {
        let (mnemonic, operands) = instruction_text(program, element.index);
        let width = 1 + operands.len() as u32;
        (Symbol::Box { mnemonic, operands }, width)
    };
    match &instruction.op {
        Op::Load { contact, .. } | Op::And(contact) | Op::Or(contact) => match contact {
            Contact::Level { bit, closed } => (
                Symbol::Contact {
                    kind: if *closed {
                        ContactKind::Closed
                    } else {
                        ContactKind::Open
                    },
                    device: bit_name(bit),
                },
                1,
            ),
            Contact::Edge { bit, falling, .. } => (
                Symbol::Contact {
                    kind: if *falling {
                        ContactKind::Falling
                    } else {
                        ContactKind::Rising
                    },
                    device: bit_name(bit),
                },
                1,
            ),
            Contact::Constant(on) => (Symbol::Constant(*on), 1),
            Contact::Compare { op, width, left, right } => {
                let double = if *width == ladder_runtime::Width::Double {
                    "D"
                } else {
                    ""
                };
                (
                    Symbol::Compare {
                        operator: format!("{double}{}", op.symbol()),
                        left: word_name(left),
                        right: word_name(right),
                    },
                    2,
                )
            }
        },
        Op::Logic(Logic::Invert) => (Symbol::Invert, 1),
        Op::Logic(Logic::ResultEdge { falling, .. }) => (Symbol::ResultEdge { falling: *falling }, 1),
        // `OUT Sn` inside a block (a transfer, as SET) is drawn as written.
        Op::Output(
            Output::Coil(bit)
            | Output::Set {
                target: bit,
                written_out: true,
                ..
            },
        ) => (
            Symbol::Coil {
                device: bit_name(bit),
                preset: None,
            },
            1,
        ),
        Op::Output(Output::Timer { timer, preset }) => (
            Symbol::Coil {
                device: format!("T{timer}"),
                preset: Some(word_name(preset)),
            },
            1,
        ),
        Op::Output(Output::Counter { counter, preset }) => (
            Symbol::Coil {
                device: format!("C{counter}"),
                preset: Some(word_name(preset)),
            },
            1,
        ),
        Op::Output(
            Output::Set { written_out: false, .. }
            | Output::Reset { .. }
            | Output::Pulse { .. }
            | Output::StateJump { .. }
            | Output::MasterControl { .. }
            | Output::App(_),
        )
        | Op::Logic(Logic::AndBlock | Logic::OrBlock | Logic::BranchPush | Logic::BranchRead | Logic::BranchPop)
        | Op::Jump { .. }
        | Op::Call { .. }
        | Op::Line(_) => boxed(),
    }
}

/// The mnemonic and operands of a box.
fn instruction_text(program: &CheckedProgram, index: usize) -> (String, Vec<String>) {
    instruction(program, index, Role::Load)
}
