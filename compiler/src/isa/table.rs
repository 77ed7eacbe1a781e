//! The table itself. Bit instructions are listed one by one; data
//! instructions as (16-bit name, 32-bit name, pulse form?) rows that expand
//! to up to four mnemonics.

use super::OperandKind::*;
use super::{Class, CompareOp, DataOp, InstrSpec, OperandKind, Role, Sense};
use std::collections::HashMap;
use std::sync::OnceLock;

const fn bit(name: &'static str, class: Class, operands: &'static [OperandKind], required: usize) -> InstrSpec {
    InstrSpec {
        name,
        class,
        operands,
        required,
        wide: false,
        pulse: false,
    }
}

const BIT_INSTRUCTIONS: &[InstrSpec] = &[
    bit("LD", Class::Contact(Role::Load, Sense::Open), &[BitSource], 1),
    bit("LDI", Class::Contact(Role::Load, Sense::Closed), &[BitSource], 1),
    bit("LDP", Class::Contact(Role::Load, Sense::Rising), &[BitSource], 1),
    bit("LDF", Class::Contact(Role::Load, Sense::Falling), &[BitSource], 1),
    bit("AND", Class::Contact(Role::And, Sense::Open), &[BitSource], 1),
    bit("ANI", Class::Contact(Role::And, Sense::Closed), &[BitSource], 1),
    bit("ANDP", Class::Contact(Role::And, Sense::Rising), &[BitSource], 1),
    bit("ANDF", Class::Contact(Role::And, Sense::Falling), &[BitSource], 1),
    bit("OR", Class::Contact(Role::Or, Sense::Open), &[BitSource], 1),
    bit("ORI", Class::Contact(Role::Or, Sense::Closed), &[BitSource], 1),
    bit("ORP", Class::Contact(Role::Or, Sense::Rising), &[BitSource], 1),
    bit("ORF", Class::Contact(Role::Or, Sense::Falling), &[BitSource], 1),
    bit("NOI", Class::AliasContact(Sense::Open), &[BitSource], 1),
    bit("NCI", Class::AliasContact(Sense::Closed), &[BitSource], 1),
    bit("PTI", Class::AliasContact(Sense::Rising), &[BitSource], 1),
    bit("NTI", Class::AliasContact(Sense::Falling), &[BitSource], 1),
    bit("ATI", Class::AliasConstant(true), &[BitSource], 0),
    bit("AFI", Class::AliasConstant(false), &[BitSource], 0),
    bit("ANB", Class::BlockAnd, &[], 0),
    bit("ORB", Class::BlockOr, &[], 0),
    bit("MPS", Class::Push, &[], 0),
    bit("MRD", Class::Read, &[], 0),
    bit("MPP", Class::Pop, &[], 0),
    bit("INV", Class::Invert, &[], 0),
    bit("MEP", Class::ResultEdge(Sense::Rising), &[], 0),
    bit("MEF", Class::ResultEdge(Sense::Falling), &[], 0),
    bit("OUT", Class::Out, &[Coil, Preset], 1),
    bit("CO", Class::Out, &[Coil, Preset], 1),
    bit("SET", Class::Set, &[BitTarget, DeviceCount], 1),
    bit("SCO", Class::Set, &[BitTarget, DeviceCount], 1),
    bit("RST", Class::Reset, &[ResetTarget, DeviceCount], 1),
    bit("RCO", Class::Reset, &[ResetTarget, DeviceCount], 1),
    bit("PLS", Class::Pulse(Sense::Rising), &[BitTarget], 1),
    bit("PLF", Class::Pulse(Sense::Falling), &[BitTarget], 1),
    bit("ST", Class::StateJump, &[State], 1),
    bit("MC", Class::MasterControl, &[NestLevel, BitTarget], 2),
    bit("MCR", Class::MasterControlReset, &[NestLevel], 1),
    bit("CJ", Class::Jump, &[Label], 1),
    bit("STL", Class::Stl, &[State], 1),
    bit("STLE", Class::StlEnd, &[], 0),
    bit("NETWORK", Class::Network, &[], 0),
    bit("POP", Class::RungEnd, &[], 0),
    bit("END", Class::End, &[], 0),
];

/// (operation, 16-bit name, 32-bit name, has P forms, operands)
type DataRow = (DataOp, &'static str, &'static str, bool, &'static [OperandKind]);

const DATA_INSTRUCTIONS: &[DataRow] = &[
    (DataOp::Mov, "MOV", "DMOV", true, &[Source, Destination]),
    (DataOp::BlockMov, "BMOV", "", true, &[Source, Destination, WordCount]),
    (
        DataOp::FillMov,
        "FMOV",
        "DFMOV",
        true,
        &[Source, Destination, WordCount],
    ),
    (DataOp::Add, "ADD", "DADD", true, &[Source, Source, Destination]),
    (DataOp::Sub, "SUB", "DSUB", true, &[Source, Source, Destination]),
    (DataOp::Mul, "MUL", "DMUL", true, &[Source, Source, WideDestination]),
    (DataOp::Div, "DIV", "DDIV", true, &[Source, Source, WideDestination]),
    (DataOp::Inc, "INC", "DINC", true, &[Destination]),
    (DataOp::Dec, "DEC", "DDEC", true, &[Destination]),
    (DataOp::Cmp, "CMP", "DCMP", true, &[Source, Source, BitTriple]),
    (
        DataOp::ZoneCmp,
        "ZCP",
        "DZCP",
        true,
        &[Source, Source, Source, BitTriple],
    ),
];

const COMPARE_ROLES: [(&str, Role); 3] = [("LD", Role::Load), ("AND", Role::And), ("OR", Role::Or)];
const COMPARE_OPS: [CompareOp; 6] = [
    CompareOp::Eq,
    CompareOp::Ne,
    CompareOp::Gt,
    CompareOp::Lt,
    CompareOp::Ge,
    CompareOp::Le,
];

fn build() -> HashMap<String, InstrSpec> {
    let mut table = HashMap::new();
    let mut add = |spec: InstrSpec| {
        let previous = table.insert(spec.name.to_string(), spec);
        debug_assert!(previous.is_none(), "mnemonic listed twice: {}", spec.name);
    };
    for spec in BIT_INSTRUCTIONS {
        add(*spec);
    }
    for &(op, narrow, wide, pulse, operands) in DATA_INSTRUCTIONS {
        for (name, is_wide) in [(narrow, false), (wide, true)] {
            if name.is_empty() {
                continue;
            }
            let required = operands.len();
            let spec = InstrSpec {
                name,
                class: Class::Data(op),
                operands,
                required,
                wide: is_wide,
                pulse: false,
            };
            add(spec);
            if pulse {
                add(InstrSpec {
                    name: generated_name(format!("{name}P")),
                    pulse: true,
                    ..spec
                });
            }
        }
    }
    for (prefix, role) in COMPARE_ROLES {
        for op in COMPARE_OPS {
            for wide in [false, true] {
                let name = format!("{prefix}{}{}", if wide { "D" } else { "" }, op.symbol());
                add(InstrSpec {
                    name: generated_name(name),
                    class: Class::Compare(role, op),
                    operands: &[Source, Source],
                    required: 2,
                    wide,
                    pulse: false,
                });
            }
        }
    }
    table
}

/// Names made from a row (MOVP, LDD>=) live as long as the table, which is
/// built once per process.
fn generated_name(name: String) -> &'static str {
    Box::leak(name.into_boxed_str())
}

fn table() -> &'static HashMap<String, InstrSpec> {
    static TABLE: OnceLock<HashMap<String, InstrSpec>> = OnceLock::new();
    TABLE.get_or_init(build)
}

/// Finds the instruction for a mnemonic, case-insensitively.
pub fn lookup(mnemonic: &str) -> Option<&'static InstrSpec> {
    table().get(&mnemonic.to_ascii_uppercase())
}

/// Every mnemonic, for suggestions and documentation.
pub fn mnemonics() -> impl Iterator<Item = &'static str> {
    table().keys().map(String::as_str)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forms_expand() {
        let movp = lookup("movp").unwrap();
        assert_eq!(
            (movp.class, movp.wide, movp.pulse),
            (Class::Data(DataOp::Mov), false, true)
        );
        let dmovp = lookup("DMOVP").unwrap();
        assert!(dmovp.wide && dmovp.pulse);
        assert!(lookup("BMOVP").is_some());
        assert!(lookup("DBMOV").is_none());
        assert_eq!(
            lookup("ANDD<>").unwrap().class,
            Class::Compare(Role::And, CompareOp::Ne)
        );
        assert!(lookup("LDD>=").unwrap().wide);
        assert!(lookup("LDX").is_none());
        assert_eq!(lookup("co").unwrap().class, Class::Out);
    }

    #[test]
    fn no_mnemonic_is_listed_twice() {
        // `build` asserts in debug builds; make sure it ran.
        assert!(mnemonics().count() > 80);
    }
}
