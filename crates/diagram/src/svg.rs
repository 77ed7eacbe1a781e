//! The ladder drawn as SVG: rails, wires, contacts, coils and boxes, the
//! step number of each rung in the margin and its comments above it.
//!
//! Every drawn element is a group with `data-e` (its instruction's index in
//! the checked program) and a `<title>` naming its source line, and every
//! rung a group with `data-rung` and `data-line`: the monitor of `ladderc
//! serve` and the HTML reports colour the same drawing by setting classes
//! on these groups (`on` for a closed contact or a driven coil) and filling
//! the value slots (`<text class="value" data-slot="k">`).

use super::layout::{layout, Cell, ContactKind, RungLayout, Symbol, Wire};
use super::monitor::{element_state, ElementState};
use super::{Ladder, Rung};
use ladder_front::program::CheckedProgram;
use quick_xml::escape::escape;
use std::fmt::Write;

/// A cell's width and a row's height, in pixels.
pub const CELL: u32 = 80;
pub const ROW: u32 = 58;
/// Where the left rail is (the step numbers go left of it).
pub const MARGIN: u32 = 64;
/// Height of one comment line above a rung.
const COMMENT: u32 = 18;
/// Space between rungs.
const GAP: u32 = 10;
/// The wire runs this far below the top of its row.
const WIRE: u32 = 28;

/// The look of the drawing, shared by every page that shows it. Comments
/// in Japanese or Chinese fall back to CJK fonts where the system has them.
pub const STYLE: &str = "\
.ladder{font-family:'DejaVu Sans Mono',Consolas,'Noto Sans Mono CJK JP','Noto Sans CJK JP','Noto Sans JP',\
'Source Han Sans','Microsoft YaHei','MS Gothic',monospace;font-size:12px}\
.ladder .rail,.ladder .wire,.ladder .sym{stroke:#222;stroke-width:1.5;fill:none}\
.ladder .rail{stroke-width:3}\
.ladder text{fill:#111;stroke:none}\
.ladder .device{font-weight:bold}\
.ladder .step{fill:#666;text-anchor:end}\
.ladder .comment{fill:#0a6b2c;font-style:italic}\
.ladder .dcomment{fill:#0a6b2c;font-size:9px}\
.ladder .label{fill:#7a2a00;font-weight:bold;text-anchor:end}\
.ladder .box rect{fill:#fff}\
.ladder .value{fill:#0b49a8}\
.ladder .on .sym{stroke:#0b5ed7;stroke-width:3}\
.ladder .on rect.fill{fill:#0b5ed7;fill-opacity:.25}\
.ladder .break .sym{stroke:#c00}\
.ladder .current>rect.band{fill:#ffe98a}\
.ladder rect.band{fill:none}\
";

/// What each element shows (by instruction index), for a drawing of a
/// program's state; `None` draws the program alone.
pub type States<'a> = Option<&'a dyn Fn(usize) -> ElementState>;

/// The whole ladder of `program` as one SVG document.
pub fn render(ladder: &Ladder, program: &CheckedProgram) -> String {
    render_states(ladder, program, None)
}

/// The ladder with the values `image` holds: closed contacts and ON coils
/// marked, values under the operands (what the monitor shows, on paper).
pub fn render_image(ladder: &Ladder, program: &CheckedProgram, image: &ladder_runtime::Memory) -> String {
    let states = |index: usize| element_state(program, index, image);
    render_states(ladder, program, Some(&states))
}

fn render_states(ladder: &Ladder, program: &CheckedProgram, states: States) -> String {
    let layouts: Vec<RungLayout> = ladder.rungs.iter().map(|r| layout(r, program)).collect();
    let columns = layouts.iter().map(|l| l.columns).max().unwrap_or(0);
    let width = MARGIN + columns * CELL + 24;
    let mut body = String::new();
    let mut y = GAP;
    for (index, (rung, laid)) in ladder.rungs.iter().zip(&layouts).enumerate() {
        y += rung_svg(&mut body, index, rung, laid, y, states);
        y += GAP;
    }
    y += end_svg(&mut body, ladder, y, columns.max(super::layout::DEFAULT_COLUMNS));
    y += GAP;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"ladder\" width=\"{width}\" height=\"{y}\" \
         viewBox=\"0 0 {width} {y}\"><title>{}</title><style>{STYLE}</style>\
         <rect width=\"100%\" height=\"100%\" fill=\"#fff\"/>{body}</svg>",
        escape(ladder.name.as_str())
    );
    out
}

/// Rung number `index` as an SVG document of its own (for pages that show
/// rungs one by one; the page supplies `STYLE`).
pub fn rung_document(index: usize, rung: &Rung, laid: &RungLayout) -> String {
    rung_drawing(index, rung, laid).0
}

/// A rung's drawing's width in pixels: the margin, its cells, the right
/// rail and a little room after it.
pub fn rung_width(laid: &RungLayout) -> u32 {
    MARGIN + laid.columns * CELL + 24
}

/// A rung's `<svg>` and its height in pixels.
pub fn rung_drawing(index: usize, rung: &Rung, laid: &RungLayout) -> (String, u32) {
    let width = rung_width(laid);
    let mut body = String::new();
    let height = rung_svg(&mut body, index, rung, laid, GAP / 2, None) + GAP;
    let drawing = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"ladder\" id=\"rung-{index}\" width=\"{width}\" \
         height=\"{height}\" viewBox=\"0 0 {width} {height}\">{body}</svg>"
    );
    (drawing, height)
}

/// A line that says what a rung is for: its first comment, else what it
/// drives (`OUT Y000, SET M0, MOV ...`).
pub fn caption(rung: &Rung, laid: &RungLayout) -> String {
    if let Some(comment) = rung.comments.last() {
        return comment.clone();
    }
    if let Some(label) = &laid.label {
        return label.clone();
    }
    let outputs: Vec<String> = laid
        .cells
        .iter()
        .filter(|c| c.column + c.width == laid.columns)
        .filter_map(|c| match &c.symbol {
            Symbol::Coil { device, .. } => Some(format!("OUT {device}")),
            Symbol::Box { mnemonic, operands } => Some(match operands.last() {
                Some(last) => format!("{mnemonic} {last}"),
                None => mnemonic.clone(),
            }),
            Symbol::Contact { .. }
            | Symbol::Compare { .. }
            | Symbol::Constant(_)
            | Symbol::Invert
            | Symbol::ResultEdge { .. } => None,
        })
        .collect();
    let shown = outputs.iter().take(3).cloned().collect::<Vec<_>>().join(", ");
    if outputs.len() > 3 {
        format!("{shown}, …")
    } else {
        shown
    }
}

/// The END every program ends with, after the last rung.
fn end_svg(out: &mut String, ladder: &Ladder, top: u32, columns: u32) -> u32 {
    let step = ladder.rungs.last().map_or(0, |r| r.step + 1);
    let (right, wire) = (MARGIN + columns * CELL, WIRE);
    let _ = write!(
        out,
        "<g class=\"end\" transform=\"translate(0,{top})\">\
         <text class=\"step\" x=\"{}\" y=\"{}\">{step}</text>\
         <line class=\"rail\" x1=\"{MARGIN}\" y1=\"0\" x2=\"{MARGIN}\" y2=\"{ROW}\"/>\
         <line class=\"rail\" x1=\"{right}\" y1=\"0\" x2=\"{right}\" y2=\"{ROW}\"/>\
         <line class=\"wire\" x1=\"{MARGIN}\" y1=\"{wire}\" x2=\"{}\" y2=\"{wire}\"/>\
         <rect class=\"sym\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"22\"/>\
         <text class=\"op\" x=\"{}\" y=\"{}\" text-anchor=\"middle\">END</text></g>",
        MARGIN - 8,
        wire + 4,
        right - CELL + 6,
        right - CELL + 6,
        wire - 11,
        CELL - 12,
        right - CELL / 2,
        wire + 4
    );
    ROW
}

/// Height of a rung as drawn (comments and rows).
pub fn rung_height(rung: &Rung, laid: &RungLayout) -> u32 {
    rung.comments.len() as u32 * COMMENT + laid.rows * ROW
}

/// Draws rung number `index` with its top at `top`; returns its height.
pub fn rung_svg(out: &mut String, index: usize, rung: &Rung, laid: &RungLayout, top: u32, states: States) -> u32 {
    let height = rung_height(rung, laid);
    let _ = write!(
        out,
        "<g class=\"rung\" data-rung=\"{index}\" data-line=\"{}\" transform=\"translate(0,{top})\">\
         <title>line {}, step {}</title><rect class=\"band\" x=\"0\" y=\"0\" width=\"{}\" height=\"{height}\"/>",
        rung.line,
        rung.line,
        rung.step,
        MARGIN + laid.columns * CELL + 12
    );
    let mut y = 0;
    for comment in &rung.comments {
        let _ = write!(
            out,
            "<text class=\"comment\" x=\"{}\" y=\"{}\">{}</text>",
            MARGIN + 6,
            y + COMMENT - 5,
            escape(comment.as_str())
        );
        y += COMMENT;
    }
    let rows_top = y;
    let wire_y = |row: u32| rows_top + row * ROW + WIRE;
    let x = |column: u32| MARGIN + column * CELL;
    // The step number as an editor shows it, and a label in the margin.
    let _ = write!(
        out,
        "<text class=\"step\" x=\"{}\" y=\"{}\">{}</text>",
        MARGIN - 8,
        wire_y(0) + 4,
        rung.step
    );
    if let Some(label) = &laid.label {
        let _ = write!(
            out,
            "<text class=\"label\" x=\"{}\" y=\"{}\">{}</text>",
            MARGIN - 8,
            wire_y(0) + 18,
            escape(label.as_str())
        );
    }
    // The rails run on through the comments and the gap to the next rung.
    let rails_bottom = height + GAP;
    for rail in [MARGIN, x(laid.columns)] {
        let _ = write!(
            out,
            "<line class=\"rail\" x1=\"{rail}\" y1=\"0\" x2=\"{rail}\" y2=\"{rails_bottom}\"/>"
        );
    }
    for wire in &laid.wires {
        let (x1, y1, x2, y2) = match *wire {
            Wire::Horizontal { row, from, to } => (x(from), wire_y(row), x(to), wire_y(row)),
            Wire::Vertical { column, from, to } => (x(column), wire_y(from), x(column), wire_y(to)),
        };
        let _ = write!(
            out,
            "<line class=\"wire\" x1=\"{x1}\" y1=\"{y1}\" x2=\"{x2}\" y2=\"{y2}\"/>"
        );
    }
    for cell in &laid.cells {
        let state = states.map(|f| f(cell.element.index));
        cell_svg(
            out,
            cell,
            x(cell.column),
            wire_y(cell.row),
            state.as_ref(),
            &rung.device_comments,
        );
    }
    for connector in &laid.connectors {
        connector_svg(out, connector, x(connector.column), wire_y(connector.row));
    }
    out.push_str("</g>");
    height
}

/// A continuation mark of a wrapped rung: `⇒n` where the wire leaves a
/// band, `n⇒` where it comes back.
fn connector_svg(out: &mut String, connector: &super::layout::Connector, left: u32, wire: u32) {
    let middle = left + CELL / 2;
    let (circle, line_from, line_to, head) = if connector.outgoing {
        (middle + 12, left, middle, middle)
    } else {
        (middle - 12, middle - 2, left + CELL, left + CELL)
    };
    let _ = write!(
        out,
        "<g class=\"connector\"><line class=\"wire\" x1=\"{line_from}\" y1=\"{wire}\" x2=\"{line_to}\" y2=\"{wire}\"/>\
         <path class=\"sym\" d=\"M{} {}L{head} {wire}L{} {}\"/>\
         <circle class=\"sym\" cx=\"{circle}\" cy=\"{wire}\" r=\"10\"/>\
         <text class=\"op\" x=\"{circle}\" y=\"{}\" text-anchor=\"middle\">{}</text></g>",
        head - 6,
        wire - 5,
        head - 6,
        wire + 5,
        wire + 4,
        connector.number
    );
}

/// One element: `left` is its cell's left edge, `wire` the wire's height.
fn cell_svg(
    out: &mut String,
    cell: &Cell,
    left: u32,
    wire: u32,
    state: Option<&ElementState>,
    comments: &std::collections::BTreeMap<String, String>,
) {
    let width = cell.width * CELL;
    let right = left + width;
    let middle = left + width / 2;
    let kind = match cell.symbol {
        Symbol::Contact { .. } | Symbol::Constant(_) | Symbol::Compare { .. } => "contact",
        Symbol::Invert | Symbol::ResultEdge { .. } => "modifier",
        Symbol::Coil { .. } => "coil",
        Symbol::Box { .. } => "box",
    };
    let note = cell
        .element
        .note
        .as_deref()
        .map(|n| format!(": {}", escape(n)))
        .unwrap_or_default();
    let marks = match state {
        Some(state) => format!(
            "{}{}",
            if state.on == Some(true) { " on" } else { "" },
            if state.forced { " forced" } else { "" }
        ),
        None => String::new(),
    };
    let _ = write!(
        out,
        "<g class=\"cell {kind}{marks}\" data-e=\"{}\"><title>line {}, step {}{note}</title>",
        cell.element.index, cell.element.line, cell.element.step
    );
    let text = |out: &mut String, class: &str, x: u32, y: u32, content: &str| {
        let _ = write!(
            out,
            "<text class=\"{class}\" x=\"{x}\" y=\"{y}\" text-anchor=\"middle\">{}</text>",
            escape(content)
        );
    };
    let value_at = |out: &mut String, slot: usize, x: u32, anchor: &str| {
        let value = state
            .and_then(|s| s.values.get(slot))
            .map_or(String::new(), |v| escape(v.as_str()).into_owned());
        let _ = write!(
            out,
            "<text class=\"value\" data-slot=\"{slot}\" x=\"{x}\" y=\"{}\" text-anchor=\"{anchor}\">{value}</text>",
            wire + 24
        );
    };
    let value_slot = |out: &mut String, slot: usize, x: u32| value_at(out, slot, x, "middle");
    let wire_to = |out: &mut String, from: u32, to: u32| {
        let _ = write!(
            out,
            "<line class=\"wire\" x1=\"{from}\" y1=\"{wire}\" x2=\"{to}\" y2=\"{wire}\"/>"
        );
    };
    let (top, bottom) = (wire - 11, wire + 11);
    // A device comment under the element, cut to the cell's width (the
    // whole comment is in the element's title).
    let device_comment = |out: &mut String, device: &str| {
        if let Some(comment) = comments.get(device) {
            // About six pixels a character at this size, twice that for
            // the wide (CJK) ones.
            let mut room = (width / 6) as usize;
            let shown: String = comment
                .chars()
                .take_while(|c| {
                    let needs = if (*c as u32) < 0x1100 { 1 } else { 2 };
                    let fits = needs <= room;
                    room = room.saturating_sub(needs);
                    fits
                })
                .collect();
            let _ = write!(
                out,
                "<text class=\"dcomment\" x=\"{middle}\" y=\"{}\" text-anchor=\"middle\">{}<title>{}</title></text>",
                wire + 31,
                escape(shown.as_str()),
                escape(comment.as_str())
            );
        }
    };
    match &cell.symbol {
        Symbol::Contact { kind, device } => {
            let (a, b) = (middle - 7, middle + 7);
            wire_to(out, left, a);
            wire_to(out, b, right);
            let _ = write!(
                out,
                "<rect class=\"fill\" x=\"{a}\" y=\"{top}\" width=\"14\" height=\"22\" fill=\"none\"/>\
                 <path class=\"sym\" d=\"M{a} {top}V{bottom}M{b} {top}V{bottom}\"/>"
            );
            match kind {
                ContactKind::Open => {}
                ContactKind::Closed => {
                    let _ = write!(out, "<path class=\"sym\" d=\"M{} {bottom}L{} {top}\"/>", a - 3, b + 3);
                }
                ContactKind::Rising => {
                    let _ = write!(
                        out,
                        "<path class=\"sym\" d=\"M{middle} {}V{}M{} {}L{middle} {}L{} {}\"/>",
                        bottom - 3,
                        top + 3,
                        middle - 4,
                        top + 8,
                        top + 3,
                        middle + 4,
                        top + 8
                    );
                }
                ContactKind::Falling => {
                    let _ = write!(
                        out,
                        "<path class=\"sym\" d=\"M{middle} {}V{}M{} {}L{middle} {}L{} {}\"/>",
                        top + 3,
                        bottom - 3,
                        middle - 4,
                        bottom - 8,
                        bottom - 3,
                        middle + 4,
                        bottom - 8
                    );
                }
            }
            text(out, "device", middle, top - 5, device);
            value_slot(out, 0, middle);
            device_comment(out, device);
        }
        Symbol::Constant(on) => {
            let (a, b) = (middle - 7, middle + 7);
            wire_to(out, left, a);
            wire_to(out, b, right);
            let _ = write!(
                out,
                "<path class=\"sym\" d=\"M{a} {top}V{bottom}M{b} {top}V{bottom}\"/>"
            );
            if !on {
                let _ = write!(out, "<path class=\"sym\" d=\"M{} {bottom}L{} {top}\"/>", a - 3, b + 3);
            }
            text(out, "device", middle, top - 5, if *on { "ATI" } else { "AFI" });
        }
        Symbol::Compare {
            operator,
            left: l,
            right: r,
        } => {
            let (a, b) = (left + 8, right - 8);
            wire_to(out, left, a);
            wire_to(out, b, right);
            let _ = write!(
                out,
                "<rect class=\"sym fill\" x=\"{a}\" y=\"{top}\" width=\"{}\" height=\"22\"/>",
                b - a
            );
            let third = (b - a) / 3;
            text(out, "op", a + third / 2, wire + 4, operator);
            text(out, "device", a + third + third / 2, wire + 4, l);
            text(out, "device", a + 2 * third + third / 2, wire + 4, r);
            value_slot(out, 0, a + third + third / 2);
            value_slot(out, 1, a + 2 * third + third / 2);
        }
        Symbol::Invert => {
            wire_to(out, left, right);
            let _ = write!(
                out,
                "<path class=\"sym\" d=\"M{} {}L{} {}\"/>",
                middle - 6,
                bottom,
                middle + 6,
                top
            );
            text(out, "op", middle, top - 5, "INV");
        }
        Symbol::ResultEdge { falling } => {
            wire_to(out, left, right);
            let (from, to, head) = if *falling {
                (top, bottom, bottom - 6)
            } else {
                (bottom, top, top + 6)
            };
            let _ = write!(
                out,
                "<path class=\"sym\" d=\"M{middle} {from}V{to}M{} {head}L{middle} {to}L{} {head}\"/>",
                middle - 5,
                middle + 5
            );
            text(out, "op", middle, top - 5, if *falling { "MEF" } else { "MEP" });
        }
        Symbol::Coil { device, preset } => {
            let (a, b) = (middle - 11, middle + 11);
            wire_to(out, left, a);
            wire_to(out, b, right);
            let _ = write!(
                out,
                "<circle class=\"fill\" cx=\"{middle}\" cy=\"{wire}\" r=\"11\" fill=\"none\"/>\
                 <path class=\"sym\" d=\"M{} {top}Q{a} {wire} {} {bottom}M{} {top}Q{b} {wire} {} {bottom}\"/>",
                a + 5,
                a + 5,
                b - 5,
                b - 5
            );
            text(out, "device", middle, top - 5, device);
            device_comment(out, device);
            match preset {
                Some(preset) => {
                    let _ = write!(
                        out,
                        "<text class=\"preset\" x=\"{}\" y=\"{}\" text-anchor=\"end\">{}</text>",
                        middle - 14,
                        wire + 22,
                        escape(preset.as_str())
                    );
                    // The preset ends left of the coil and the current value
                    // starts right of it, so that neither runs into the other
                    // however long they are.
                    value_at(out, 0, middle + 14, "start");
                }
                None => value_slot(out, 0, middle),
            }
        }
        Symbol::Box { mnemonic, operands } => {
            let (a, b) = (left + 6, right - 6);
            wire_to(out, left, a);
            wire_to(out, b, right);
            let _ = write!(
                out,
                "<rect class=\"sym fill\" x=\"{a}\" y=\"{top}\" width=\"{}\" height=\"22\"/>",
                b - a
            );
            let part = (b - a) / (1 + operands.len() as u32);
            text(out, "op", a + part / 2, wire + 4, mnemonic);
            for (k, operand) in operands.iter().enumerate() {
                let at = a + part * (k as u32 + 1) + part / 2;
                text(out, "device", at, wire + 4, operand);
                value_slot(out, k, at);
            }
        }
    }
    out.push_str("</g>");
}
