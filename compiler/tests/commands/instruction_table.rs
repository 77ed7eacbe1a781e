//! Checks against the instruction table, so that a new instruction cannot
//! be half added:
//!
//! - docs/language.md holds the tables generated from the declarations
//!   (`LADDER_BLESS=1 cargo test -p ladderc --test commands instruction_table`
//!   regenerates them) and so names every mnemonic;
//! - every mnemonic is used by at least one scenario under testsuite/;
//! - the differential test's generator can produce every application form.

use crate::common;

use ladder_front::isa::reference;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("workspace")
        .to_path_buf()
}

/// Replaces (bless) or checks the block after `<!-- generated: NAME -->`.
fn generated_block(text: &mut String, name: &str, content: &str, bless: bool) -> Result<(), String> {
    let start_marker = format!("<!-- generated: {name} -->\n");
    let end_marker = "<!-- end of generated block -->";
    let start = text
        .find(&start_marker)
        .ok_or(format!("no `{start_marker}` in docs/language.md"))?
        + start_marker.len();
    let end = start
        + text[start..]
            .find(end_marker)
            .ok_or("an unterminated generated block")?;
    if bless {
        text.replace_range(start..end, content);
        return Ok(());
    }
    if text[start..end] != *content {
        return Err(format!(
            "docs/language.md: the generated block `{name}` is out of date; regenerate it with\n  \
             LADDER_BLESS=1 cargo test -p ladderc --test commands instruction_table\n--- expected ---\n{content}"
        ));
    }
    Ok(())
}

#[test]
fn language_reference_holds_the_generated_tables() {
    let path = workspace().join("docs/language.md");
    let mut text = std::fs::read_to_string(&path).unwrap();
    let bless = std::env::var_os("LADDER_BLESS").is_some();
    let mut problems = Vec::new();
    for (name, content) in [
        ("application instructions", reference::application_tables()),
        ("mnemonic index", reference::bit_mnemonics()),
    ] {
        if let Err(problem) = generated_block(&mut text, name, &content, bless) {
            problems.push(problem);
        }
    }
    if bless {
        std::fs::write(&path, text).unwrap();
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_mnemonic_is_in_the_language_reference() {
    let text = std::fs::read_to_string(workspace().join("docs/language.md")).unwrap();
    let words: BTreeSet<&str> = text
        .split(|c: char| c.is_whitespace() || "`|,.;:()".contains(c))
        .collect();
    let missing: Vec<&str> = ladder_front::isa::mnemonics()
        .into_iter()
        .filter(|m| !words.contains(m))
        .collect();
    assert!(missing.is_empty(), "not in docs/language.md: {missing:?}");
}

/// Every `.scn` file's text and every program file (IL or a CSV export,
/// decoded as ladderc reads it).
fn scenario_texts() -> Vec<String> {
    let mut texts = Vec::new();
    let mut pending = vec![workspace().join("testsuite")];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "scn" || e == "il" || e == "csv") {
                texts.push(ladder_front::source::SourceFile::read(&path).unwrap().text);
            }
        }
    }
    texts
}

#[test]
fn every_mnemonic_is_used_by_a_scenario() {
    let mut used = BTreeSet::new();
    for text in scenario_texts() {
        for line in text.lines() {
            let line = line.split(['#', ';']).next().unwrap_or("");
            let mut words = line.split_whitespace();
            // An optional step number first, as in program files.
            let first = words.next();
            let mnemonic = match first {
                Some(word) if word.bytes().all(|b| b.is_ascii_digit()) => words.next(),
                other => other,
            };
            if let Some(mnemonic) = mnemonic {
                used.insert(mnemonic.to_ascii_uppercase());
            }
        }
    }
    let missing: Vec<&str> = ladder_front::isa::mnemonics()
        .into_iter()
        .filter(|m| !used.contains(*m))
        .collect();
    assert!(missing.is_empty(), "no scenario under testsuite/ uses: {missing:?}");
}

#[test]
fn the_generator_knows_every_application_form() {
    let forms: BTreeSet<String> = common::vocabulary::app_forms()
        .into_iter()
        .map(|(name, ..)| name)
        .collect();
    for mnemonic in ladder_front::isa::mnemonics() {
        if let Some(ladder_front::isa::Mnemonic::App(_)) = ladder_front::isa::lookup(mnemonic) {
            assert!(
                forms.contains(mnemonic),
                "the differential generator cannot produce {mnemonic}"
            );
        }
    }
}

/// The FX3U instructions ladderc does not implement are listed once
/// (`isa::fx::UNSUPPORTED_FX`, E0032): none of them is also declared, and
/// docs/language.md's table of them names exactly that list, so an
/// instruction that becomes supported leaves both.
#[test]
fn the_unsupported_list_and_its_table_agree_with_the_instruction_set() {
    use ladder_front::isa::fx::UNSUPPORTED_FX;
    let declared: BTreeSet<String> = ladder_front::isa::mnemonics().into_iter().map(str::to_string).collect();
    let both: Vec<&&str> = UNSUPPORTED_FX.iter().filter(|m| declared.contains(**m)).collect();
    assert!(both.is_empty(), "declared and listed as not supported: {both:?}");
    let text = std::fs::read_to_string(workspace().join("docs/language.md")).unwrap();
    let section = text
        .split("### FX3U instructions that are not supported")
        .nth(1)
        .expect("the section of unsupported instructions");
    let section = section.split("\n#").next().unwrap_or(section);
    let in_table: BTreeSet<&str> = section
        .lines()
        .filter_map(|line| line.strip_prefix("| "))
        .filter_map(|row| row.split(" |").next())
        .filter(|cell| !cell.starts_with("instructions") && !cell.starts_with("---"))
        .flat_map(|cell| cell.split(", "))
        .map(str::trim)
        .collect();
    let listed: BTreeSet<&str> = UNSUPPORTED_FX.iter().copied().collect();
    assert_eq!(
        in_table, listed,
        "docs/language.md's table of unsupported instructions against isa::fx::UNSUPPORTED_FX"
    );
}
