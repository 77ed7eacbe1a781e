//! `ladderc test --html DIR`: a page per failing scenario and engine that
//! shows what went wrong as a PLC engineer looks at it — the ladder at the
//! scan of each failed expectation (contacts closed, coils ON, values under
//! the operands, as the engine left them) and the waveform of the devices
//! the scenario touches, with the failures marked on it.

use ladder_diagram::{self as ladder, svg};
use ladder_engine::scenario::EngineRun;
use ladder_engine::waveform::Recorder;
use ladder_front::program::CheckedProgram;
use ladder_front::source::SourceFile;
use quick_xml::escape::escape;
use std::fmt::Write as _;

/// Pixels per lane of the waveform, and for the names left of it.
const LANE: u32 = 26;
const NAMES: u32 = 150;
const WAVE_WIDTH: u32 = 900;

/// The page for one engine's failed run of scenario `title`.
pub fn page(title: &str, run: &EngineRun, program: &CheckedProgram, source: &SourceFile) -> String {
    let diagram = ladder::build(program, source);
    let mut body = String::new();
    let _ = write!(
        body,
        "<h1>{}</h1><p>engine <b>{}</b> · program {}</p>",
        escape(title),
        run.kind.name(),
        escape(source.name.as_str())
    );
    if let Some(waveform) = &run.waveform {
        body.push_str("<h2>Waveform</h2>");
        body.push_str(&waveform_svg(
            waveform,
            &run.snapshots.iter().map(|s| s.time_ms).collect::<Vec<_>>(),
        ));
    }
    if run.snapshots.is_empty() {
        body.push_str("<p>This engine keeps no image the report could show (the object-file engine runs in a process of its own); the page of the interpreter or the JIT shows the ladder.</p>");
    }
    for snapshot in &run.snapshots {
        let _ = write!(
            body,
            "<h2 class=\"failure\">line {}: {} <small>(after scan {}, {} ms)</small></h2>",
            snapshot.line,
            escape(snapshot.message.as_str()),
            snapshot.scan,
            snapshot.time_ms
        );
        body.push_str("<div class=\"ladder-box\">");
        body.push_str(&svg::render_image(&diagram, program, &snapshot.image));
        body.push_str("</div>");
    }
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{} — {}</title>\
         <style>body{{font-family:system-ui,sans-serif;margin:16px}} h1{{font-size:18px}} \
         h2{{font-size:15px;margin-top:20px}} .failure{{color:#b00}} small{{color:#555;font-weight:normal}} \
         .ladder-box{{overflow:auto;max-height:80vh;border:1px solid #ccc}} \
         .wave text{{font:11px monospace}} .wave .trace{{fill:none;stroke:#1f5fbf;stroke-width:1.5}} \
         .wave .fail{{stroke:#d00;stroke-width:1.5}} .wave .grid{{stroke:#ddd}}</style></head>\
         <body>{body}</body></html>\n",
        escape(title),
        run.kind.name()
    )
}

/// The recorded devices over time: a lane each, bits high or low, values
/// as steps labelled where they change; the failures as red lines.
fn waveform_svg(waveform: &Recorder, failures: &[u64]) -> String {
    let signals = waveform.signals();
    let samples = waveform.samples();
    let end = waveform.end_ms().max(samples.last().map_or(0, |s| s.0)).max(1);
    let height = LANE * signals.len() as u32 + 24;
    let x = |t: u64| NAMES as f64 + WAVE_WIDTH as f64 * t as f64 / end as f64;
    let mut out = String::new();
    let _ = write!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"wave\" width=\"{}\" height=\"{height}\">",
        NAMES + WAVE_WIDTH + 20
    );
    // Time axis: ten ticks.
    for tick in 0..=10u64 {
        let t = end * tick / 10;
        let px = x(t);
        let _ = write!(
            out,
            "<line class=\"grid\" x1=\"{px:.1}\" y1=\"0\" x2=\"{px:.1}\" y2=\"{}\"/><text x=\"{px:.1}\" y=\"{}\" text-anchor=\"middle\">{t} ms</text>",
            height - 16,
            height - 4
        );
    }
    for (lane, signal) in signals.iter().enumerate() {
        let top = LANE * lane as u32;
        let (high, low) = (f64::from(top + 4), f64::from(top + LANE - 6));
        let _ = write!(
            out,
            "<text x=\"4\" y=\"{}\">{}</text>",
            top + LANE / 2 + 4,
            escape(signal.name.as_str())
        );
        let bit = signal.device.bits() == 1 && !signal.real;
        // Where this device's value changes: (time, value).
        let mut changes: Vec<(u64, i32)> = Vec::new();
        for (time, values) in samples {
            let value = values.get(lane).copied().unwrap_or(0);
            if changes.last().is_none_or(|&(_, last)| last != value) {
                changes.push((*time, value));
            }
        }
        let mut path = String::new();
        for (index, &(time, value)) in changes.iter().enumerate() {
            let next = changes.get(index + 1).map_or(end, |c| c.0);
            let (from, to) = (x(time), x(next));
            if bit {
                let y = if value != 0 { high } else { low };
                let _ = write!(
                    path,
                    "{}{from:.1} {y:.1}L{to:.1} {y:.1}",
                    if index == 0 { "M" } else { "L" }
                );
            } else {
                // A bus: a box per value, the value written in it.
                let _ = write!(
                    out,
                    "<rect x=\"{from:.1}\" y=\"{high:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"#eef3fb\" stroke=\"#1f5fbf\"/>\
                     <text x=\"{:.1}\" y=\"{:.1}\">{}</text>",
                    (to - from).max(0.5),
                    low - high,
                    from + 3.0,
                    low - 4.0,
                    escape(signal.show(value, |v, _| v.to_string()).as_str())
                );
            }
        }
        if !path.is_empty() {
            let _ = write!(out, "<path class=\"trace\" d=\"{path}\"/>");
        }
    }
    for &t in failures {
        let px = x(t);
        let _ = write!(
            out,
            "<line class=\"fail\" x1=\"{px:.1}\" y1=\"0\" x2=\"{px:.1}\" y2=\"{}\"/>",
            height - 16
        );
    }
    out.push_str("</svg>");
    out
}
