//! `ladderc render`: the program drawn as a ladder diagram, as SVG or as a
//! page of HTML to open in a browser. Like every command that writes a
//! file, it writes only when the program compiles and never over an input.

use super::{output, read_program, status, write_raw};
use clap::{Args, ValueEnum};
use ladder_diagram::{self as ladder, svg};
use ladder_front::diagnostics::Shown;
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
    let (program, diagnostics) = ladder_front::check::compile_source(&source);
    write_raw(
        true,
        &ladder_front::diagnostics::render_all(&source, &diagnostics, shown),
    );
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
    let document = match format {
        Format::Svg => svg::render(&diagram, &program),
        Format::Html => page(&diagram, &program, &source.name),
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

/// A page with a rung index beside the rungs, one SVG each.
fn page(diagram: &ladder::Ladder, program: &ladder_front::program::CheckedProgram, file: &str) -> String {
    use std::fmt::Write as _;
    let mut index = String::new();
    let mut rungs = String::new();
    for (number, rung) in diagram.rungs.iter().enumerate() {
        let laid = ladder::layout::layout(rung, program);
        let _ = write!(
            index,
            "<li><a href=\"#rung-{number}\"><span class=\"step\">{}</span> {}</a></li>",
            rung.step,
            escape(svg::caption(rung, &laid).as_str())
        );
        rungs.push_str(&svg::rung_document(number, rung, &laid));
    }
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>{title} — ladder</title>\
         <style>{style}\
         body{{margin:0;font-family:system-ui,sans-serif;display:grid;grid-template-columns:260px 1fr;height:100vh}}\
         nav{{overflow:auto;border-right:1px solid #ccc;background:#f6f6f6;font-size:13px}}\
         nav h1{{font-size:15px;margin:10px 12px}} nav p{{margin:0 12px 8px;color:#555}}\
         nav ol{{list-style:none;margin:0;padding:0}} nav a{{display:block;padding:2px 12px;color:#123;\
         text-decoration:none;white-space:nowrap;overflow:hidden;text-overflow:ellipsis}}\
         nav a:hover{{background:#e2e8f0}} nav .step{{display:inline-block;width:44px;color:#666;text-align:right;\
         margin-right:6px}} main{{overflow:auto}} main svg{{display:block}}</style></head>\
         <body><nav><h1>{title}</h1><p>{file} · {count} rungs</p><ol>{index}</ol></nav>\
         <main>{rungs}</main></body></html>\n",
        style = svg::STYLE,
        title = escape(diagram.name.as_str()),
        file = escape(file),
        count = diagram.rungs.len(),
    )
}
