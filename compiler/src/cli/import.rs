//! `ladderc import`: an instruction-list export (GX Works2, GX Developer, a
//! step CSV) as plain IL, so that a team can keep the program as text in
//! version control. An export is written only when it compiles: otherwise
//! its diagnostics are printed (at the export's own lines) and nothing is
//! written, so an imported file always compiles.

use super::{output, status, write_raw};
use ladder_front::diagnostics::Shown;
use ladder_front::source::SourceFile;
use ladder_front::syntax::export;
use std::io::Write as _;
use std::path::{Path, PathBuf};

pub fn run(export: &Path, output_path: Option<&PathBuf>, shown: Shown) -> u8 {
    let source = match SourceFile::read(export) {
        Ok(source) => source,
        Err(error) => {
            say_err!("error: {error}");
            return status::UNUSABLE;
        }
    };
    if !export::is_export(&source.text) {
        say_err!(
            "error: {} is not an instruction-list export (rows of step, line statement, instruction, operand, ... \
             separated by tabs or commas, as GX Works2 and GX Developer write them); plain IL needs no import",
            export.display()
        );
        return status::UNUSABLE;
    }
    // Checked before converting: a refused output is refused however the
    // export is.
    let target = match output_path.map(|path| output::prepare(path, &[export])) {
        None => None,
        Some(Ok(target)) => Some(target),
        Some(Err(error)) => {
            say_err!("error: {error}");
            return status::UNUSABLE;
        }
    };
    if source.undecodable_at.is_some() || source.text.contains('\0') {
        // Not text: the front end's one diagnostic (E0046 or E0009), and
        // nothing is written.
        let (_, diagnostics) = ladder_front::check::compile_source(&source);
        write_raw(
            true,
            &ladder_front::diagnostics::render_all(&source, &diagnostics, shown),
        );
        return status::FAILED;
    }
    // An export that does not compile is not written.
    let (program, diagnostics) = ladder_front::check::compile_source(&source);
    if program.is_none() {
        write_raw(
            true,
            &ladder_front::diagnostics::render_all(&source, &diagnostics, shown),
        );
        return status::FAILED;
    }
    let il = match export::to_il(&source) {
        Ok(il) => il,
        Err(diagnostics) => {
            let diagnostics = diagnostics.into_sorted();
            write_raw(
                true,
                &ladder_front::diagnostics::render_all(&source, &diagnostics, shown),
            );
            return status::FAILED;
        }
    };
    match target {
        None => {
            let _ = std::io::stdout().lock().write_all(il.as_bytes());
            status::OK
        }
        Some(path) => match output::write_atomically(&path, il.as_bytes()) {
            Ok(()) => status::OK,
            Err(error) => {
                say_err!("error: cannot write {}: {error}", path.display());
                status::FAILED
            }
        },
    }
}
