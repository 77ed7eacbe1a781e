//! The mnemonic table: every bit instruction and every form of every
//! application instruction, built once from their declarations.

use super::app::AppOp;
use super::bits::{comparison_contacts, BitSpec, BIT_INSTRUCTIONS};
use ladder_runtime::Width;
use rustc_hash::FxHashMap;
use std::sync::OnceLock;

/// What a mnemonic names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mnemonic {
    Bit(&'static BitSpec),
    App(AppForm),
}

/// One form of an application instruction: `DMOVP` is MOV, 32-bit, pulse.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AppForm {
    pub op: AppOp,
    pub width: Width,
    pub pulse: bool,
}

fn build() -> FxHashMap<String, Mnemonic> {
    let mut table = FxHashMap::default();
    let mut add = |name: &str, mnemonic: Mnemonic| {
        let previous = table.insert(name.to_string(), mnemonic);
        debug_assert!(previous.is_none(), "mnemonic listed twice: {name}");
    };
    for spec in BIT_INSTRUCTIONS {
        add(spec.name, Mnemonic::Bit(spec));
    }
    for spec in comparison_contacts() {
        let spec: &'static BitSpec = Box::leak(Box::new(spec));
        add(spec.name, Mnemonic::Bit(spec));
    }
    for &op in AppOp::ALL {
        for (name, width, pulse) in op.spec().mnemonics() {
            add(&name, Mnemonic::App(AppForm { op, width, pulse }));
        }
    }
    table
}

fn table() -> &'static FxHashMap<String, Mnemonic> {
    static TABLE: OnceLock<FxHashMap<String, Mnemonic>> = OnceLock::new();
    TABLE.get_or_init(build)
}

/// Finds the instruction for a mnemonic, case-insensitively.
pub fn lookup(mnemonic: &str) -> Option<Mnemonic> {
    // The parser hands mnemonics over in capitals already: no copy then.
    if mnemonic.bytes().any(|b| b.is_ascii_lowercase()) {
        table().get(&mnemonic.to_ascii_uppercase()).copied()
    } else {
        table().get(mnemonic).copied()
    }
}

/// Every mnemonic, sorted: for suggestions and documentation checks.
pub fn mnemonics() -> Vec<&'static str> {
    let mut names: Vec<&'static str> = table().keys().map(String::as_str).collect();
    names.sort_unstable();
    names
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::isa::{BitClass, CompareOp, Role};

    #[test]
    fn forms_expand() {
        let Some(Mnemonic::App(movp)) = lookup("movp") else {
            panic!("MOVP")
        };
        assert_eq!((movp.op, movp.width, movp.pulse), (AppOp::Mov, Width::Single, true));
        let Some(Mnemonic::App(dmovp)) = lookup("DMOVP") else {
            panic!("DMOVP")
        };
        assert!(dmovp.width == Width::Double && dmovp.pulse);
        assert!(lookup("BMOVP").is_some());
        assert!(lookup("DBMOV").is_none());
        let Some(Mnemonic::Bit(andd)) = lookup("ANDD<>") else {
            panic!("ANDD<>")
        };
        assert_eq!(andd.class, BitClass::Compare(Role::And, CompareOp::Ne));
        assert!(matches!(lookup("LDD>="), Some(Mnemonic::Bit(s)) if s.width == Width::Double));
        assert!(lookup("LDX").is_none());
        assert!(matches!(lookup("co"), Some(Mnemonic::Bit(s)) if s.class == BitClass::Out));
    }

    #[test]
    fn no_mnemonic_is_listed_twice() {
        // `build` asserts in debug builds; make sure it ran.
        assert!(mnemonics().len() > 80);
    }
}
