//! docs/runtime.md lists every runtime helper with its C prototype and what
//! it does, as declared in `src/helpers.rs`.

use ladder_runtime::helpers::Helper;
use std::path::Path;

fn row(helper: Helper) -> String {
    let decl = helper.decl();
    format!("| `{}` | {} |", decl.c_prototype(), decl.doc.trim())
}

#[test]
fn every_helper_is_documented_as_declared() {
    let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/runtime.md");
    let text = std::fs::read_to_string(&docs).expect("docs/runtime.md");
    let missing: Vec<String> = Helper::ALL
        .iter()
        .map(|&helper| row(helper))
        .filter(|row| !text.contains(row.as_str()))
        .collect();
    assert!(
        missing.is_empty(),
        "docs/runtime.md does not list these helpers as declared; the rows should read:\n{}",
        missing.join("\n")
    );
    // No helper that no longer exists.
    for line in text
        .lines()
        .filter(|l| l.starts_with("| `") && l.contains(" ladder_rt_"))
    {
        assert!(
            Helper::ALL.iter().any(|&h| row(h) == line),
            "docs/runtime.md lists a helper that is not declared: {line}"
        );
    }
}
