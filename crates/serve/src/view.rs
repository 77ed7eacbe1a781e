//! The ladder the monitor page shows: drawn once per program (when it is
//! loaded, off the scan thread), handed to the page a window of rungs at a
//! time, then coloured from the published image for the rungs the page has
//! on screen only; and the devices the program uses, which the page's
//! device table starts with.

use ladder_diagram::layout::{Cell, Symbol};
use ladder_runtime::Device;

use ladder_diagram::{self as ladder, monitor::element_state, svg};
use ladder_front::program::CheckedProgram;
use ladder_front::source::SourceFile;
use ladder_runtime::{BitArea, Memory};
use serde_json::{json, Value};

pub struct LadderView {
    pub program: CheckedProgram,
    /// One `<svg>` per rung (`id="rung-N"`).
    pub drawings: Vec<String>,
    /// Each drawing's height in pixels, so that the page can place a rung
    /// before it has the drawing.
    pub heights: Vec<u32>,
    /// The elements (instruction indices) of each rung.
    pub rungs: Vec<Vec<usize>>,
    /// The widest drawing's width in pixels (the page fits it to its pane).
    pub width: u32,
    /// The devices the program uses, as the watch list names them: its Y
    /// outputs, then its X inputs (each in order), then the others in the
    /// order they first appear; at most `DEFAULT_WATCHED`.
    pub devices: Vec<String>,
    /// The program's device comments (`X000` → text), for the table.
    pub comments: ladder::DeviceComments,
}

/// The most devices the device table starts with.
pub const DEFAULT_WATCHED: usize = 64;

impl LadderView {
    pub fn new(program: &CheckedProgram, source: &SourceFile) -> LadderView {
        let diagram = ladder::build(program, source);
        let mut drawings = Vec::with_capacity(diagram.rungs.len());
        let mut heights = Vec::with_capacity(diagram.rungs.len());
        let mut rungs = Vec::with_capacity(diagram.rungs.len());
        let mut width = 0;
        let mut used = Used::default();
        for (index, rung) in diagram.rungs.iter().enumerate() {
            let laid = ladder::layout::layout(rung, program);
            let (drawing, height) = svg::rung_drawing(index, rung, &laid);
            drawings.push(drawing);
            heights.push(height);
            width = width.max(svg::rung_width(&laid));
            rungs.push(laid.cells.iter().map(|c| c.element.index).collect());
            laid.cells.iter().for_each(|cell| used.cell(cell));
        }
        LadderView {
            program: program.clone(),
            drawings,
            heights,
            rungs,
            width,
            devices: used.devices(),
            comments: std::sync::Arc::new(ladder_front::gxdev::listing::device_comments(&source.text)),
        }
    }

    /// Every rung as one HTML fragment, with the drawing's style.
    pub fn fragment(&self) -> String {
        let mut fragment = format!("<style>{}</style>", svg::STYLE);
        for drawing in &self.drawings {
            fragment.push_str(drawing);
        }
        fragment
    }

    /// The states of the elements of `rungs` in `image`: `[index, on, forced,
    /// [values]]` with `on` 1, 0 or null.
    pub fn states(&self, rungs: &[usize], image: &Memory) -> Value {
        let elements: Vec<Value> = rungs
            .iter()
            .filter_map(|&rung| self.rungs.get(rung))
            .flatten()
            .map(|&index| {
                let state = element_state(&self.program, index, image);
                json!([index, state.on.map(u8::from), u8::from(state.forced), state.values])
            })
            .collect();
        Value::Array(elements)
    }
}

/// The devices the cells of a program name, by kind, each once.
#[derive(Default)]
struct Used {
    outputs: Vec<(u32, String)>,
    inputs: Vec<(u32, String)>,
    others: Vec<String>,
    seen: std::collections::HashSet<String>,
}

impl Used {
    fn cell(&mut self, cell: &Cell) {
        match &cell.symbol {
            Symbol::Contact { device, .. } | Symbol::Coil { device, .. } => self.name(device),
            Symbol::Compare { left, right, .. } => {
                self.name(left);
                self.name(right);
            }
            Symbol::Box { operands, .. } => operands.iter().for_each(|operand| self.name(operand)),
            Symbol::Constant(_) | Symbol::Invert | Symbol::ResultEdge { .. } => {}
        }
    }

    /// An operand as the diagram shows it (`X000`, `D10`, `K4M0`); what
    /// the watch list cannot name (a constant, an indexed device) is left.
    fn name(&mut self, text: &str) {
        let Ok(signals) = ladder_engine::watch::parse_watch(text) else {
            return;
        };
        let [signal] = signals.as_slice() else {
            return;
        };
        if !self.seen.insert(signal.name.clone()) {
            return;
        }
        let name = signal.name.clone();
        match signal.device.device {
            Device::Bit(BitArea::Y, n) => self.outputs.push((n, name)),
            Device::Bit(BitArea::X, n) => self.inputs.push((n, name)),
            Device::Bit(..) | Device::Word(..) | Device::WordBit(..) | Device::Digits(..) | Device::WideCounter(_) => {
                self.others.push(name)
            }
        }
    }

    fn devices(mut self) -> Vec<String> {
        self.outputs.sort_unstable();
        self.inputs.sort_unstable();
        let outputs = self.outputs.into_iter().map(|(_, name)| name);
        let inputs = self.inputs.into_iter().map(|(_, name)| name);
        outputs.chain(inputs).chain(self.others).take(DEFAULT_WATCHED).collect()
    }
}

/// Every forced device of `image`: (name, value).
pub fn forces(image: &Memory) -> Vec<(String, bool)> {
    let mut out = Vec::new();
    for area in [
        BitArea::X,
        BitArea::Y,
        BitArea::M,
        BitArea::TimerContact,
        BitArea::CounterContact,
    ] {
        for index in 0..area.count() {
            if let Some(on) = image.forced(area, index) {
                let name = match area {
                    BitArea::X | BitArea::Y => format!("{}{index:o}", area.prefix()),
                    BitArea::TimerContact => format!("T{index}"),
                    BitArea::CounterContact => format!("C{index}"),
                    BitArea::M | BitArea::S | BitArea::Sm => format!("{}{index}", area.prefix()),
                };
                out.push((name, on));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_device_table_starts_with_the_outputs_then_the_inputs_the_program_uses() {
        let text = "LD X1\nOR Y2\nANI X10\nOUT Y2\nLD X3\nMOV K5 D10\nOUT T0 K10\nLD T0\nOUT Y0\nLD= D10 K5\nOUT M7\n";
        let source = SourceFile::new("plc.il", text.to_string());
        let (Some(program), _) = ladder_front::check::compile_source(&source) else {
            panic!("the program compiles");
        };
        let view = LadderView::new(&program, &source);
        assert_eq!(
            view.devices,
            ["Y000", "Y002", "X001", "X003", "X010", "D10", "T0", "M7"]
        );
        assert!(view.width > 12 * ladder_diagram::svg::CELL, "{}", view.width);
    }
}
