//! The runtime's committed C header (`runtime/include/ladder_runtime.h`)
//! matches its C API in `runtime/src/capi/mod.rs`.

use crate::common::tools::workspace;

#[test]
fn c_header_is_current() {
    let root = workspace().join("runtime");
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
        "include/ladder_runtime.h is out of date; regenerate it with\n  LADDER_BLESS=1 cargo test -p ladderc --test commands c_header\n--- generated ---\n{}",
        String::from_utf8_lossy(&generated)
    );
}
