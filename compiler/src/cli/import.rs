//! `ladderc import`: an instruction-list export (GX Works2, GX Developer, a
//! step CSV) or a GX Developer project as plain IL, so that a team can keep
//! the program as text in version control; and with `--to-gx-developer`
//! the way back, a program written as a GX Developer project's MAIN.wpg
//! and COMMENT.wcd. An export is written only when it compiles: otherwise
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
    // A GX Developer project: its listing is the IL.
    let project = source.listing_of.is_some() || source.decode_error.is_some();
    if !project && !export::is_export(&source.text) {
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
    let converted = if project {
        Ok(source.text.clone())
    } else {
        export::to_il(&source)
    };
    let il = match converted {
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

/// `ladderc import PROG --to-gx-developer DIR`: the program (IL, an export
/// or a project) written as the MAIN.wpg and COMMENT.wcd of the project in
/// DIR. The CPU and program memory come from the program's `//@` lines,
/// else from DIR's param.wpa, else GX Developer's defaults (FX3U, 8000
/// steps); the program is checked against that CPU. Only a program that
/// compiles is written, and both files or neither (`output::
/// write_all_atomically`); a program without `//@ comment` lines keeps the
/// project's COMMENT.wcd. A failed command leaves nothing new behind (no
/// folders either).
pub fn to_gx_developer(program: &Path, dir: &Path, shown: Shown) -> u8 {
    use ladder_front::gxdev;
    let source = match SourceFile::read(program) {
        Ok(source) => source,
        Err(error) => {
            say_err!("error: {error}");
            return status::UNUSABLE;
        }
    };
    // The project's parameters first: the program is checked against the
    // CPU it will be written for.
    let files = gxdev::Project::in_folder(dir);
    let mut defaults = gxdev::write::Defaults::default();
    if files.parameters.exists() {
        let bytes = match ladder_front::source::read_bounded(&files.parameters) {
            Ok(bytes) => bytes,
            Err(error) => {
                say_err!("error: {error}");
                return status::UNUSABLE;
            }
        };
        match gxdev::wpa::decode(&bytes) {
            Ok(parameters) => {
                defaults.cpu = Some(parameters.cpu);
                defaults.memory = parameters.memory;
            }
            Err(error) => {
                say_err!("error: {}", error.message(&files.parameters.display().to_string()));
                return status::UNUSABLE;
            }
        }
    }
    let cpu = defaults
        .cpu
        .map_or(Some(gxdev::write::DEFAULT_CPU), gxdev::wpa::cpu_name);
    let (checked, diagnostics) = ladder_front::check::compile_source_on(&source, cpu);
    write_raw(
        true,
        &ladder_front::diagnostics::render_all(&source, &diagnostics, shown),
    );
    if checked.is_none() {
        return status::FAILED;
    }
    // An export is encoded from its IL (its comments become statements).
    let source = if export::is_export(&source.text) {
        match export::to_il(&source) {
            Ok(il) => SourceFile::new(source.name.clone(), il),
            Err(_) => return status::FAILED,
        }
    } else {
        source
    };
    let (main, comments) = match gxdev::write::encode(&source, &defaults) {
        Ok(bytes) => bytes,
        Err(message) => {
            say_err!("error: {message}");
            return status::FAILED;
        }
    };
    // Without `//@ comment` lines the program says nothing about comments:
    // the project's own stay.
    let keep_comments = gxdev::listing::directives(&source.text).comments.is_empty() && files.comments.is_file();
    let mut made = Vec::new();
    let code = write_project(
        &files,
        (&main, (!keep_comments).then_some(&comments)),
        program,
        &mut made,
    );
    if code != status::OK {
        // The folders this run made go again (the deepest first; a folder
        // that is not empty stays).
        for folder in made.iter().rev() {
            let _ = std::fs::remove_dir(folder);
        }
    }
    code
}

/// Makes the project's missing folders (each recorded in `made`) and writes
/// MAIN.wpg and, when given, COMMENT.wcd.
fn write_project(
    files: &ladder_front::gxdev::Project,
    (main, comments): (&[u8], Option<&Vec<u8>>),
    program: &Path,
    made: &mut Vec<PathBuf>,
) -> u8 {
    let targets: Vec<(&Path, &[u8])> = std::iter::once((files.program.as_path(), main))
        .chain(comments.map(|bytes| (files.comments.as_path(), bytes.as_slice())))
        .collect();
    for (file, _) in &targets {
        let missing: Vec<&Path> = file
            .ancestors()
            .skip(1)
            .filter(|folder| !folder.as_os_str().is_empty())
            .take_while(|folder| !folder.exists())
            .collect();
        for folder in missing.into_iter().rev() {
            if let Err(error) = std::fs::create_dir(folder) {
                say_err!("error: cannot make {}: {error}", folder.display());
                return status::FAILED;
            }
            made.push(folder.to_path_buf());
        }
    }
    let mut prepared = Vec::with_capacity(targets.len());
    for (file, bytes) in &targets {
        match output::prepare(file, &[program]) {
            Ok(target) => prepared.push((target, *bytes)),
            Err(error) => {
                say_err!("error: {error}");
                return status::UNUSABLE;
            }
        }
    }
    let writes: Vec<(&Path, &[u8])> = prepared.iter().map(|(path, bytes)| (path.as_path(), *bytes)).collect();
    match output::write_all_atomically(&writes) {
        Ok(()) => status::OK,
        Err((path, error)) => {
            say_err!("error: cannot write {}: {error}", path.display());
            status::FAILED
        }
    }
}
