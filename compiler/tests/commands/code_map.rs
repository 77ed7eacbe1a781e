//! docs/architecture.md's code map is true to the code: every source folder
//! has its entry, every source file is named in its folder's entry, and every
//! file an entry names exists.

use crate::common::tools::workspace;
use std::path::{Path, PathBuf};

/// The code map's entries: the folder each names first, and its text.
fn entries(architecture: &str) -> Vec<(String, String)> {
    let section = architecture
        .split("\n## Code map\n")
        .nth(1)
        .expect("docs/architecture.md has a `## Code map` section");
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

fn source_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        if path.is_dir() {
            source_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs" || e == "c" || e == "html") {
            out.push(path);
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
                && [".rs", ".c", ".html"].iter().any(|extension| name.ends_with(extension))
                && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.')
        })
        .collect()
}

#[test]
fn every_source_file_is_in_the_code_map_and_every_name_in_it_exists() {
    let root = workspace();
    let text = std::fs::read_to_string(root.join("docs/architecture.md")).unwrap();
    let entries = entries(&text);
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
    let mut problems = Vec::new();
    for file in &files {
        let relative = file.strip_prefix(&root).unwrap();
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
    for (folder, entry) in &entries {
        if !root.join(folder).is_dir() {
            problems.push(format!("{folder}: the code map names a folder that does not exist"));
            continue;
        }
        for name in named_files(entry) {
            if !root.join(folder).join(name).is_file() {
                problems.push(format!("{folder}: the entry names `{name}`, which is not there"));
            }
        }
    }
    assert!(
        problems.is_empty(),
        "docs/architecture.md's code map:\n{}",
        problems.join("\n")
    );
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
