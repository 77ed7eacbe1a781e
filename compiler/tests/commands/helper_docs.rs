//! docs/runtime.md lists every runtime helper with its C prototype and what
//! it does, as declared in `runtime/src/helpers.rs`. `LADDER_BLESS=1 cargo test -p
//! ladderc --test commands helper_docs` rewrites the table from the
//! declarations.

use crate::common::tools::workspace;
use ladder_runtime::helpers::Helper;

const TABLE_HEADER: &str = "| C prototype | does |\n|---|---|\n";

fn row(helper: Helper) -> String {
    let decl = helper.decl();
    let doc: Vec<&str> = decl
        .doc
        .lines()
        .map(str::trim)
        .filter(|line| !line.is_empty())
        .collect();
    format!("| `{}` | {} |", decl.c_prototype(), doc.join(" "))
}

fn table() -> String {
    let rows: Vec<String> = Helper::ALL.iter().map(|&h| row(h)).collect();
    format!("{TABLE_HEADER}{}\n", rows.join("\n"))
}

#[test]
fn every_helper_is_documented_as_declared() {
    let docs = workspace().join("docs/runtime.md");
    let text = std::fs::read_to_string(&docs).expect("docs/runtime.md");
    let start = text.find(TABLE_HEADER).expect("the helper table in docs/runtime.md");
    let end = text[start..].find("\n\n").map_or(text.len(), |i| start + i + 1);
    if std::env::var_os("LADDER_BLESS").is_some() {
        let updated = format!("{}{}{}", &text[..start], table(), &text[end..]);
        std::fs::write(&docs, updated).expect("docs/runtime.md written");
        return;
    }
    assert_eq!(
        &text[start..end],
        table(),
        "docs/runtime.md's helper table is out of date; regenerate it with\n  LADDER_BLESS=1 cargo test -p ladderc --test commands helper_docs"
    );
}
