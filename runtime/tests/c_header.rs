//! The committed C header matches the C API in `src/capi/mod.rs`.

use std::path::Path;

#[test]
fn c_header_is_current() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(root.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(root.join("src/capi/mod.rs"))
        .generate()
        .expect("cbindgen reads the C API");
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let path = root.join("include/ladder_runtime.h");
    if std::env::var_os("LADDER_BLESS").is_some() {
        std::fs::write(&path, &generated).expect("header written");
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "include/ladder_runtime.h is out of date; regenerate it with\n  LADDER_BLESS=1 cargo test -p ladder-runtime --test c_header\n--- generated ---\n{}",
        String::from_utf8_lossy(&generated)
    );
}
