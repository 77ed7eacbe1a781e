//! GX Developer projects, read as programs and written back: the folder
//! with `Gppw.gps`, its program `Pou/Body/MAIN.wpg`, its device comments
//! `Others/COMMENT.wcd` and its PLC parameters `param.wpa`.
//!
//! Reading makes an IL listing of the project (`listing.rs`): one line per
//! instruction with its step number first, `//@` lines for the CPU, the
//! program memory, the latched ranges and the device comments. The front
//! end compiles the listing as any IL, so diagnostics show the step; a file
//! that cannot be decoded is one error naming its byte offset and what was
//! expected there. Writing encodes an IL program (and its `//@` lines) as
//! MAIN.wpg and COMMENT.wcd; the other files of a project are kept.

pub mod listing;
pub mod records;
pub mod text;
pub mod wcd;
pub mod wpa;
pub mod wpg;
pub mod write;

use std::path::{Path, PathBuf};

/// Where a file cannot be decoded, and what was expected there.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DecodeError {
    pub offset: usize,
    pub expected: String,
}

impl DecodeError {
    pub fn new(offset: usize, expected: impl Into<String>) -> DecodeError {
        DecodeError {
            offset,
            expected: expected.into(),
        }
    }

    /// The message for file `name`.
    pub fn message(&self, name: &str) -> String {
        format!(
            "{name} cannot be decoded: at byte offset {} (0x{:X}), expected {}",
            self.offset, self.offset, self.expected
        )
    }
}

/// The files of a project.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Project {
    pub program: PathBuf,
    pub comments: PathBuf,
    pub parameters: PathBuf,
}

impl Project {
    /// The files of the project in folder `dir` (they need not exist).
    pub fn in_folder(dir: &Path) -> Project {
        Project {
            program: dir.join("Pou").join("Body").join("MAIN.wpg"),
            comments: dir.join("Others").join("COMMENT.wcd"),
            parameters: dir.join("param.wpa"),
        }
    }
}

/// The project `path` names: a folder holding `Gppw.gps` (or a program),
/// a project's `.gps`/`.gpw` file, or a program file in a project's
/// `Pou/Body` folder. A lone program file is recognised by its content
/// (`is_gx_file`), not here.
pub fn locate(path: &Path) -> Option<Project> {
    if path.is_dir() {
        let project = Project::in_folder(path);
        return (path.join("Gppw.gps").is_file() || project.program.is_file()).then_some(project);
    }
    let extension = path.extension()?.to_str()?.to_ascii_lowercase();
    match extension.as_str() {
        "gps" | "gpw" => locate(
            path.parent()
                .filter(|p| !p.as_os_str().is_empty())
                .unwrap_or(Path::new(".")),
        ),
        "wpg" => {
            let body = path.parent()?;
            let dir = body.parent()?.parent()?;
            let is_body = body.file_name()? == "Body" && body.parent()?.file_name()? == "Pou";
            is_body.then(|| Project {
                program: path.to_path_buf(),
                ..Project::in_folder(dir)
            })
        }
        _ => None,
    }
}

/// Does a file start as GX Developer's files do (the header mark)?
pub fn is_gx_file(bytes: &[u8]) -> bool {
    bytes.starts_with(&[records::HEADER_LEN as u8, 0x00, 0x22, 0x01])
}

/// A file of a project that cannot be decoded: its name and where.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Undecodable {
    pub file: String,
    pub error: DecodeError,
}

impl std::fmt::Display for Undecodable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.error.message(&self.file))
    }
}

/// Why a project cannot be read: a file that cannot be read (missing, no
/// permission: as any unreadable input) or one that cannot be decoded.
#[derive(Debug)]
pub enum ReadFailure {
    Read(crate::source::ReadError),
    Decode(Undecodable),
}

/// The listing of a project read from `program`'s bytes and the comment and
/// parameter files' bytes where the project has them. `Err` names the one
/// file that cannot be decoded.
pub fn listing_of(
    program: (&str, &[u8]),
    comments: Option<(&str, &[u8])>,
    parameters: Option<(&str, &[u8])>,
) -> Result<String, Undecodable> {
    let undecodable = |file: &str| {
        let file = file.to_string();
        move |error| Undecodable { file, error }
    };
    let comments = comments
        .map(|(name, bytes)| wcd::decode(bytes).map_err(undecodable(name)))
        .transpose()?;
    let parameters = parameters
        .map(|(name, bytes)| wpa::decode(bytes).map_err(undecodable(name)))
        .transpose()?;
    // The code page is guessed from all the texts: the comments and the
    // program's statements.
    let program_file = wpg::decode(program.1).map_err(undecodable(program.0))?;
    // The program memory the parameters declare is the size of MAIN.wpg
    // (GX Developer fills it with NOPs): another size is a cut or padded
    // file.
    let declared = parameters.as_ref().and_then(|p| p.memory);
    if let Some(memory) = declared.filter(|&memory| memory != program_file.capacity) {
        return Err(undecodable(program.0)(DecodeError::new(
            program.1.len(),
            format!(
                "{memory} steps of program memory, as the parameters declare (the file holds {} steps: cut short or padded?)",
                program_file.capacity
            ),
        )));
    }
    let raw: Vec<&[u8]> = comments
        .iter()
        .flat_map(|c| c.entries.iter().map(|(_, _, bytes)| bytes.as_slice()))
        .chain(program_file.lines.iter().filter_map(|line| match &line.kind {
            wpg::LineKind::Statement(text) | wpg::LineKind::Note(text) => Some(text.as_slice()),
            wpg::LineKind::Instruction { .. } | wpg::LineKind::Label(_) => None,
        }))
        .collect();
    let non_ascii = raw.iter().copied().flatten().any(|b| !b.is_ascii());
    let encoding = text::Encoding::guess(raw.iter().copied());
    let directives = listing::Directives {
        cpu: wpa::cpu_name(program_file.cpu).map(str::to_string),
        memory: parameters
            .as_ref()
            .and_then(|p| p.memory)
            .or(Some(program_file.capacity)),
        latch: parameters.as_ref().map(|p| {
            let fixed = fixed_latched(wpa::cpu_name(program_file.cpu).unwrap_or_default());
            let all: Vec<&str> = p
                .latched
                .iter()
                .map(String::as_str)
                .chain(fixed.iter().copied())
                .collect();
            all.join(",")
        }),
        encoding: non_ascii.then_some(encoding),
        comments: comments
            .iter()
            .flat_map(|c| &c.entries)
            .filter_map(|(device, number, bytes)| Some((wcd::device_name(*device, *number)?, encoding.decode(bytes))))
            .collect(),
        comment_file: None,
    };
    Ok(listing::write(&directives, &program_file.lines, encoding))
}

/// The ranges a CPU keeps through a power cut whatever its parameters say
/// (the FX2N and FX3U programming manuals' device tables); the parameters
/// set the others.
fn fixed_latched(cpu: &str) -> &'static [&'static str] {
    match cpu {
        "FX2N" => &["M1024-M3071", "T246-T255", "D512-D7999"],
        "FX3U" => &["M1024-M7679", "S1000-S4095", "T246-T255", "D512-D7999", "R0-R32767"],
        _ => &[],
    }
}

/// Reads the project's files (a missing comment or parameter file is no
/// error) and makes its listing; `Err` is the first file that cannot be
/// read or decoded.
pub fn read(project: &Project) -> Result<String, ReadFailure> {
    let read = |path: &Path| crate::source::read_bounded(path).map_err(ReadFailure::Read);
    let program = read(&project.program)?;
    let optional = |path: &Path| path.is_file().then(|| read(path)).transpose();
    let comments = optional(&project.comments)?;
    let parameters = optional(&project.parameters)?;
    let name = |path: &Path| path.display().to_string();
    let (program_name, comments_name, parameters_name) = (
        name(&project.program),
        name(&project.comments),
        name(&project.parameters),
    );
    listing_of(
        (&program_name, &program),
        comments.as_deref().map(|b| (comments_name.as_str(), b)),
        parameters.as_deref().map(|b| (parameters_name.as_str(), b)),
    )
    .map_err(ReadFailure::Decode)
}

#[cfg(test)]
mod tests;
