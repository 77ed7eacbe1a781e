//! `ladderc render`: the program drawn as a ladder diagram, as SVG or as a
//! page of HTML to open in a browser. Like every command that writes a
//! file, it writes only when the program compiles and never over an input.

use super::{output, read_program, status, write_raw};
use crate::diagnostics::Shown;
use crate::ladder::{self, svg};
use clap::{Args, ValueEnum};
use quick_xml::escape::escape;
use std::io::Write as _;
use std::path::{Path, PathBuf};

#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The program: IL or an instruction-list export (`-` reads standard input).
    pub program: PathBuf,
    /// Where to write the drawing (default: standard output).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// SVG, or an HTML page with the drawing; by default the output's
    /// extension decides (`.html`, `.htm`), else SVG.
    #[arg(long, value_enum)]
    pub format: Option<Format>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    Svg,
    Html,
}

pub fn run(args: &RenderArgs, shown: Shown) -> u8 {
    let source = match read_program(&args.program) {
        Ok(source) => source,
        Err(error) => {
            say_err!("error: {error}");
            return status::UNUSABLE;
        }
    };
    let target = match args.output.as_ref().map(|path| output::prepare(path, &[&args.program])) {
        None => None,
        Some(Ok(target)) => Some(target),
        Some(Err(error)) => {
            say_err!("error: {error}");
            return status::UNUSABLE;
        }
    };
    let (program, diagnostics) = crate::check::compile_source(&source);
    write_raw(true, &crate::diagnostics::render_all(&source, &diagnostics, shown));
    let Some(program) = program else {
        return status::FAILED;
    };
    let format = args
        .format
        .unwrap_or_else(|| match args.output.as_deref().map(extension) {
            Some(Some(e)) if e == "html" || e == "htm" => Format::Html,
            Some(_) | None => Format::Svg,
        });
    let diagram = ladder::build(&program, &source);
    let drawing = svg::render(&diagram, &program);
    let document = match format {
        Format::Svg => drawing,
        Format::Html => page(&diagram.name, &source.name, diagram.rungs.len(), &drawing),
    };
    match target {
        None => {
            let _ = std::io::stdout().lock().write_all(document.as_bytes());
            status::OK
        }
        Some(path) => match output::write_atomically(&path, document.as_bytes()) {
            Ok(()) => status::OK,
            Err(error) => {
                say_err!("error: cannot write {}: {error}", path.display());
                status::FAILED
            }
        },
    }
}

fn extension(path: &Path) -> Option<String> {
    path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase())
}

/// A page that shows the drawing (scrolls sideways when it is wide).
fn page(name: &str, file: &str, rungs: usize, drawing: &str) -> String {
    let drawing = drawing.trim_start_matches(|c| c != '<');
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>{title} — ladder</title>\
         <style>body{{margin:0;font-family:system-ui,sans-serif}}\
         header{{padding:8px 16px;border-bottom:1px solid #ccc;background:#f6f6f6}}\
         main{{overflow:auto}}</style></head>\
         <body><header><strong>{title}</strong> · {file} · {rungs} rungs</header>\
         <main>{drawing}</main></body></html>\n",
        title = escape(name),
        file = escape(file),
    )
}
