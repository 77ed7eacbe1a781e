//! The maps of the code are true to it, both ways:
//!
//! - docs/architecture.md's code map: every source folder has its entry,
//!   every source file is named in its folder's entry, and every file an
//!   entry names exists;
//! - its test map: every folder of tests has its entry naming every `.rs`
//!   file in it. The folders are every `tests/` folder of a workspace member
//!   (and its subfolders: a test binary's folder) and the fuzz targets'
//!   folders. Every file is named, a test binary's `main.rs` and the helper
//!   modules of `common/` included: a newcomer looks for the random program
//!   generator there as much as for a test, and a rule with no exceptions
//!   cannot be argued around;
//! - README.md's Layout table: every top-level folder (but hidden ones and
//!   `target/`) and every workspace member (the root Cargo.toml's `members`)
//!   has its row; a member inside a folder (`crates/front`) may instead be
//!   named in its folder's row (`` `front/` ``); every row names a folder
//!   that exists.

use crate::common::tools::workspace;
use std::path::{Path, PathBuf};

/// The folders of fuzz targets, named in the test map like test folders.
const FUZZ_TARGET_FOLDERS: &[&str] = &["fuzz/fuzz_targets", "fuzz/afl"];

/// The entries of a map section (`- `folder/`: text`, continued on the
/// lines below): the folder each names first, and its text.
fn entries(architecture: &str, heading: &str) -> Vec<(String, String)> {
    let section = architecture
        .split(&format!("\n## {heading}\n"))
        .nth(1)
        .unwrap_or_else(|| panic!("docs/architecture.md has a `## {heading}` section"));
    let section = section.split("\n## ").next().unwrap_or(section);
    let mut entries: Vec<(String, String)> = Vec::new();
    for line in section.lines() {
        if let Some(rest) = line.strip_prefix("- `") {
            let folder = rest.split('`').next().unwrap_or_default().to_string();
            entries.push((folder, rest.to_string()));
        } else if let Some((_, text)) = entries.last_mut() {
            text.push(' ');
            text.push_str(line.trim());
        }
    }
    entries
}

/// The files under `dir` whose extension is one of `extensions`, leaving
/// out build output (`target/`) and hidden folders.
pub(crate) fn files_under(dir: &Path, extensions: &[&str], out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        if path.is_dir() {
            if name != "target" && !name.starts_with('.') {
                files_under(&path, extensions, out);
            }
        } else if path
            .extension()
            .is_some_and(|e| extensions.iter().any(|wanted| e == *wanted))
        {
            out.push(path);
        }
    }
}

fn source_files(dir: &Path, out: &mut Vec<PathBuf>) {
    files_under(dir, &["rs", "c", "html"], out);
}

/// The workspace's members, as the root Cargo.toml's `members` lists them
/// (paths such as `crates/front`).
pub(crate) fn workspace_members(root: &Path) -> Vec<String> {
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap();
    let list = manifest
        .lines()
        .skip_while(|line| !line.trim_start().starts_with("members = ["))
        .skip(1)
        .take_while(|line| !line.trim_start().starts_with(']'));
    let members: Vec<String> = list
        .filter_map(|line| line.split('"').nth(1))
        .map(str::to_string)
        .collect();
    assert!(members.len() > 10, "read the workspace's members: {members:?}");
    members
}

/// The `tests/` folders under `dir` (a member's own, and any deeper).
fn test_folders(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        if !path.is_dir() || name == "target" || name.starts_with('.') {
            continue;
        }
        if name == "tests" {
            out.push(path);
        } else {
            test_folders(&path, out);
        }
    }
}

/// The names a text gives in backticks that look like source files.
fn named_files(text: &str) -> Vec<&str> {
    text.split('`')
        .skip(1)
        .step_by(2)
        .filter(|name| {
            !name.contains('/')
                && [".rs", ".c", ".html", ".py"]
                    .iter()
                    .any(|extension| name.ends_with(extension))
                && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.')
        })
        .collect()
}

/// What a map gets wrong about `files`: a file whose folder has no entry or
/// whose entry does not name it, and entries naming folders or files that
/// are not there.
fn map_problems(root: &Path, entries: &[(String, String)], files: &[PathBuf]) -> Vec<String> {
    let mut problems = Vec::new();
    for file in files {
        let relative = file.strip_prefix(root).unwrap();
        let folder = format!("{}/", relative.parent().unwrap().display());
        let name = file.file_name().unwrap().to_string_lossy();
        match entries.iter().find(|(entry, _)| *entry == folder) {
            None => problems.push(format!("{folder}: no entry for this folder ({name})")),
            Some((_, entry)) if !entry.contains(&format!("`{name}`")) => {
                problems.push(format!("{folder}: its entry does not name `{name}`"))
            }
            Some(_) => {}
        }
    }
    for (folder, entry) in entries {
        if !root.join(folder).is_dir() {
            problems.push(format!("{folder}: the map names a folder that does not exist"));
            continue;
        }
        for name in named_files(entry) {
            if !root.join(folder).join(name).is_file() {
                problems.push(format!("{folder}: the entry names `{name}`, which is not there"));
            }
        }
    }
    problems
}

#[test]
fn every_source_file_is_in_the_code_map_and_every_name_in_it_exists() {
    let root = workspace();
    let text = std::fs::read_to_string(root.join("docs/architecture.md")).unwrap();
    let entries = entries(&text, "Code map");
    let mut roots = vec![root.join("runtime/src"), root.join("compiler/src")];
    for crate_dir in std::fs::read_dir(root.join("crates")).unwrap() {
        roots.push(crate_dir.unwrap().path().join("src"));
    }
    let mut files = Vec::new();
    for dir in &roots {
        source_files(dir, &mut files);
    }
    files.sort();
    assert!(files.len() > 150, "found the sources: {}", files.len());
    let problems = map_problems(&root, &entries, &files);
    assert!(
        problems.is_empty(),
        "docs/architecture.md's code map:\n{}",
        problems.join("\n")
    );
}

#[test]
fn every_test_file_is_in_the_test_map_and_every_name_in_it_exists() {
    let root = workspace();
    let text = std::fs::read_to_string(root.join("docs/architecture.md")).unwrap();
    let entries = entries(&text, "Test map");
    let mut folders = Vec::new();
    for member in workspace_members(&root) {
        test_folders(&root.join(member), &mut folders);
    }
    folders.extend(FUZZ_TARGET_FOLDERS.iter().map(|folder| root.join(folder)));
    let mut files = Vec::new();
    for folder in &folders {
        files_under(folder, &["rs"], &mut files);
    }
    files.sort();
    assert!(files.len() > 50, "found the test files: {}", files.len());
    let problems = map_problems(&root, &entries, &files);
    assert!(
        problems.is_empty(),
        "docs/architecture.md's test map:\n{}",
        problems.join("\n")
    );
}

/// README.md's Layout table: each row's path (its first cell, `` `path/` ``)
/// and its text.
fn layout_rows(readme: &str) -> Vec<(String, String)> {
    let section = readme
        .split("\n## Layout\n")
        .nth(1)
        .expect("README.md has a `## Layout` section");
    let section = section.split("\n## ").next().unwrap_or(section);
    section
        .lines()
        .filter_map(|line| line.strip_prefix("| `"))
        .map(|row| (row.split('`').next().unwrap_or_default().to_string(), row.to_string()))
        .collect()
}

#[test]
fn every_folder_and_member_has_its_row_in_the_readme_layout() {
    let root = workspace();
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    let rows = layout_rows(&readme);
    let row = |path: &str| rows.iter().find(|(row, _)| row == path);
    let mut problems = Vec::new();
    for entry in std::fs::read_dir(&root).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap_or_default().to_string_lossy().to_string();
        if path.is_dir() && name != "target" && !name.starts_with('.') && row(&format!("{name}/")).is_none() {
            problems.push(format!("`{name}/`: a top-level folder without its row"));
        }
    }
    for member in workspace_members(&root) {
        if row(&format!("{member}/")).is_some() {
            continue;
        }
        let named_in_its_folder = member.rsplit_once('/').is_some_and(|(folder, name)| {
            row(&format!("{folder}/")).is_some_and(|(_, text)| text.contains(&format!("`{name}/`")))
        });
        if !named_in_its_folder {
            problems.push(format!(
                "`{member}/`: a workspace member without its row (or its name in its folder's)"
            ));
        }
    }
    for (path, _) in &rows {
        if !root.join(path).is_dir() {
            problems.push(format!("`{path}`: a row for a folder that does not exist"));
        }
    }
    assert!(problems.is_empty(), "README.md's Layout:\n{}", problems.join("\n"));
}

/// The project's documents stand on their own: a clone has nothing outside
/// the repository, so nothing may point there.
#[test]
fn documents_link_nothing_outside_the_repository() {
    let root = workspace();
    let mut files = vec![root.join("README.md")];
    for entry in std::fs::read_dir(root.join("docs")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "md") {
            files.push(path);
        }
    }
    let mut problems = Vec::new();
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        for (number, line) in text.lines().enumerate() {
            for outside in ["DIALECT.md", "SCENARIO.md", "../shared", "](../../"] {
                if line.contains(outside) {
                    problems.push(format!("{}:{}: `{outside}`", file.display(), number + 1));
                }
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
