//! Bit instructions (contacts, coils, rung structure, program control): one
//! row each. Their operands are positional and checked by class in
//! `check`; comparison contacts are generated from their roles and
//! operators.

use super::{BitClass, CompareOp, Role, Sense};
use ladder_runtime::Width;

/// One row of the bit-instruction table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BitSpec {
    pub name: &'static str,
    pub class: BitClass,
    /// Fewest operands.
    pub required: usize,
    /// Most operands.
    pub most: usize,
    /// 32-bit comparison contacts (`LDD=`); 16-bit otherwise.
    pub width: Width,
}

const fn bit(name: &'static str, class: BitClass, required: usize, most: usize) -> BitSpec {
    BitSpec {
        name,
        class,
        required,
        most,
        width: Width::Single,
    }
}

pub const BIT_INSTRUCTIONS: &[BitSpec] = &[
    bit("LD", BitClass::Contact(Role::Load, Sense::Open), 1, 1),
    bit("LDI", BitClass::Contact(Role::Load, Sense::Closed), 1, 1),
    bit("LDP", BitClass::Contact(Role::Load, Sense::Rising), 1, 1),
    bit("LDF", BitClass::Contact(Role::Load, Sense::Falling), 1, 1),
    bit("AND", BitClass::Contact(Role::And, Sense::Open), 1, 1),
    bit("ANI", BitClass::Contact(Role::And, Sense::Closed), 1, 1),
    bit("ANDP", BitClass::Contact(Role::And, Sense::Rising), 1, 1),
    bit("ANDF", BitClass::Contact(Role::And, Sense::Falling), 1, 1),
    bit("OR", BitClass::Contact(Role::Or, Sense::Open), 1, 1),
    bit("ORI", BitClass::Contact(Role::Or, Sense::Closed), 1, 1),
    bit("ORP", BitClass::Contact(Role::Or, Sense::Rising), 1, 1),
    bit("ORF", BitClass::Contact(Role::Or, Sense::Falling), 1, 1),
    bit("NOI", BitClass::AliasContact(Sense::Open), 1, 1),
    bit("NCI", BitClass::AliasContact(Sense::Closed), 1, 1),
    bit("PTI", BitClass::AliasContact(Sense::Rising), 1, 1),
    bit("NTI", BitClass::AliasContact(Sense::Falling), 1, 1),
    bit("ATI", BitClass::AliasConstant(true), 0, 1),
    bit("AFI", BitClass::AliasConstant(false), 0, 1),
    bit("ANB", BitClass::BlockAnd, 0, 0),
    bit("ORB", BitClass::BlockOr, 0, 0),
    bit("MPS", BitClass::BranchPush, 0, 0),
    bit("MRD", BitClass::BranchRead, 0, 0),
    bit("MPP", BitClass::BranchPop, 0, 0),
    bit("INV", BitClass::Invert, 0, 0),
    bit("MEP", BitClass::ResultEdge(Sense::Rising), 0, 0),
    bit("MEF", BitClass::ResultEdge(Sense::Falling), 0, 0),
    bit("OUT", BitClass::Out, 1, 2),
    bit("CO", BitClass::Out, 1, 2),
    bit("SET", BitClass::Set, 1, 2),
    bit("SCO", BitClass::Set, 1, 2),
    bit("RST", BitClass::Reset, 1, 2),
    bit("RCO", BitClass::Reset, 1, 2),
    bit("PLS", BitClass::Pulse(Sense::Rising), 1, 1),
    bit("PLF", BitClass::Pulse(Sense::Falling), 1, 1),
    bit("ST", BitClass::StateJump, 1, 1),
    bit("MC", BitClass::MasterControl, 2, 2),
    bit("MCR", BitClass::MasterControlReset, 1, 1),
    bit("CJ", BitClass::Jump, 1, 1),
    bit("STL", BitClass::Stl, 1, 1),
    bit("STLE", BitClass::StlEnd { fx_return: false }, 0, 0),
    bit("RET", BitClass::StlEnd { fx_return: true }, 0, 0),
    bit("FEND", BitClass::MainEnd, 0, 0),
    bit("CALL", BitClass::Call { pulse: false }, 1, 1),
    bit("CALLP", BitClass::Call { pulse: true }, 1, 1),
    bit("SRET", BitClass::SubroutineReturn, 0, 0),
    bit("FOR", BitClass::LoopStart, 1, 1),
    bit("NEXT", BitClass::LoopEnd, 0, 0),
    bit("NOP", BitClass::Nop, 0, 0),
    bit("NETWORK", BitClass::Network, 0, 0),
    bit("POP", BitClass::RungEnd, 0, 0),
    bit("END", BitClass::End, 0, 0),
];

/// Comparison contacts: `LD=`, `AND<>`, `OR>`, ... and their 32-bit forms
/// `LDD=`, `ANDD<>`, ...
pub fn comparison_contacts() -> Vec<BitSpec> {
    const ROLES: [(&str, Role); 3] = [("LD", Role::Load), ("AND", Role::And), ("OR", Role::Or)];
    let mut specs = Vec::new();
    for (prefix, role) in ROLES {
        for op in CompareOp::ALL {
            for width in [Width::Single, Width::Double] {
                let wide = if width == Width::Double { "D" } else { "" };
                specs.push(BitSpec {
                    name: leak(format!("{prefix}{wide}{}", op.symbol())),
                    class: BitClass::Compare(role, op),
                    required: 2,
                    most: 2,
                    width,
                });
            }
        }
    }
    specs
}

/// Names made from a row (LDD>=) live as long as the table, which is built
/// once per process.
fn leak(name: String) -> &'static str {
    Box::leak(name.into_boxed_str())
}
