//! The instruction tables of docs/language.md, generated from the
//! declarations (a test keeps the document current).

use super::app::{AppOp, Family};
use super::bits::{comparison_contacts, BIT_INSTRUCTIONS};
use super::operand::DeviceClass;

/// The device table of an operand as the reference shows it.
fn devices(decl: &super::OperandDecl, has_wide_form: bool) -> String {
    decl.devices
        .classes()
        .filter(|&class| has_wide_form || class != DeviceClass::WideCounter)
        .map(DeviceClass::name)
        .collect::<Vec<_>>()
        .join(" ")
}

/// One markdown table per family of application instructions.
pub fn application_tables() -> String {
    let mut out = String::new();
    for family in Family::ALL {
        let ops: Vec<AppOp> = AppOp::ALL
            .iter()
            .copied()
            .filter(|op| op.spec().family == family)
            .collect();
        if ops.is_empty() {
            continue;
        }
        out.push_str(&format!("#### {}\n\n", family.title()));
        out.push_str("| instruction | forms | does | operands |\n|---|---|---|---|\n");
        for op in ops {
            let spec = op.spec();
            let forms: Vec<String> = spec.mnemonics().into_iter().map(|(name, ..)| name).collect();
            let mut does = spec.summary.to_string();
            if !spec.writes.is_empty() {
                let flags: Vec<String> = spec.writes.iter().map(|f| f.name()).collect();
                does.push_str(&format!("; writes {}", flags.join(" ")));
            }
            let operands: Vec<String> = spec
                .operands
                .iter()
                .map(|decl| {
                    format!(
                        "{}: {}",
                        decl.name.to_ascii_uppercase(),
                        devices(decl, spec.wide_name.is_some())
                    )
                })
                .collect();
            out.push_str(&format!(
                "| `{}` | {} | {} | {} |\n",
                spec.format(),
                forms.join(" "),
                does,
                if operands.is_empty() {
                    "none".to_string()
                } else {
                    operands.join("; ")
                }
            ));
        }
        out.push('\n');
    }
    out
}

/// Every bit-instruction mnemonic, and every comparison contact.
pub fn bit_mnemonics() -> String {
    let plain: Vec<&str> = BIT_INSTRUCTIONS.iter().map(|spec| spec.name).collect();
    let comparisons: Vec<&str> = comparison_contacts().iter().map(|spec| spec.name).collect();
    format!(
        "Bit instructions: {}.\n\nComparison contacts: {}.\n",
        plain.join(" "),
        comparisons.join(" ")
    )
}
