//! The ladder the monitor page shows: drawn once per program (when it is
//! loaded, off the scan thread), handed to the page a window of rungs at a
//! time, then coloured from the published image for the rungs the page has
//! on screen only.

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
    /// The program's device comments (`X000` → text), for the table.
    pub comments: ladder::DeviceComments,
}

impl LadderView {
    pub fn new(program: &CheckedProgram, source: &SourceFile) -> LadderView {
        let diagram = ladder::build(program, source);
        let mut drawings = Vec::with_capacity(diagram.rungs.len());
        let mut heights = Vec::with_capacity(diagram.rungs.len());
        let mut rungs = Vec::with_capacity(diagram.rungs.len());
        for (index, rung) in diagram.rungs.iter().enumerate() {
            let laid = ladder::layout::layout(rung, program);
            let (drawing, height) = svg::rung_drawing(index, rung, &laid);
            drawings.push(drawing);
            heights.push(height);
            rungs.push(laid.cells.iter().map(|c| c.element.index).collect());
        }
        LadderView {
            program: program.clone(),
            drawings,
            heights,
            rungs,
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
