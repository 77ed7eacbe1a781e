//! `modelDescription.xml` for FMI 3.0 and 2.0 co-simulation: the time
//! (FMI 3.0's independent variable), the scan period as a parameter, and
//! the devices (inputs with a start value; outputs calculated, so listed
//! as outputs and initial unknowns). Outputs depend on no input directly
//! (`dependencies=""`): a step's scans see the inputs set before it, so a
//! master coupling the FMU in a loop has no algebraic loop to solve. Device names are letters, digits and
//! `:`, so nothing needs escaping but the program's name.

use crate::{Causality, FmiVersion, FmuOptions, VarType, Variable};
use std::fmt::Write as _;

/// Value references before the devices (the C wrapper's `VR_*`).
const VR_TIME: u32 = 0;
const VR_SCAN_PERIOD: u32 = 1;
const VR_FIRST_DEVICE: u32 = 2;

fn escape(text: &str) -> String {
    // Control characters have no place in XML 1.0.
    let text: String = text.chars().filter(|c| !c.is_control()).collect();
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn device_vr(index: usize) -> u32 {
    VR_FIRST_DEVICE + index as u32
}

pub fn model_description(options: &FmuOptions, identifier: &str, token: &str, variables: &[Variable]) -> String {
    match options.fmi {
        FmiVersion::Three => fmi3(options, identifier, token, variables),
        FmiVersion::Two => fmi2(options, identifier, token, variables),
    }
}

fn period_seconds(options: &FmuOptions) -> String {
    format!("{}", f64::from(options.period_ms) / 1000.0)
}

fn header(out: &mut String, version: &str, options: &FmuOptions, token_attribute: &str, token: &str) {
    let name = escape(&options.model_name);
    let _ = writeln!(out, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    let _ = writeln!(
        out,
        "<fmiModelDescription fmiVersion=\"{version}\" modelName=\"{name}\" {token_attribute}=\"{token}\"\n  \
         description=\"The ladder program {name}, scanned every scan_period\"\n  \
         generationTool=\"ladderc {}\" variableNamingConvention=\"flat\">",
        env!("CARGO_PKG_VERSION")
    );
}

fn fmi3(options: &FmuOptions, identifier: &str, token: &str, variables: &[Variable]) -> String {
    let period = period_seconds(options);
    let mut out = String::new();
    header(&mut out, "3.0", options, "instantiationToken", token);
    let _ = writeln!(
        out,
        "  <CoSimulation modelIdentifier=\"{identifier}\" canHandleVariableCommunicationStepSize=\"true\"\n    \
         canGetAndSetFMUState=\"true\" canSerializeFMUState=\"true\"/>"
    );
    let _ = writeln!(out, "  <DefaultExperiment startTime=\"0\" stepSize=\"{period}\"/>");
    let _ = writeln!(out, "  <ModelVariables>");
    let _ = writeln!(
        out,
        "    <Float64 name=\"time\" valueReference=\"{VR_TIME}\" causality=\"independent\" variability=\"continuous\"/>"
    );
    let _ = writeln!(
        out,
        "    <Float64 name=\"scan_period\" valueReference=\"{VR_SCAN_PERIOD}\" causality=\"parameter\" \
         variability=\"fixed\" start=\"{period}\" min=\"0.001\" max=\"60\" description=\"seconds between scans\"/>"
    );
    for (index, variable) in variables.iter().enumerate() {
        let element = match variable.ty {
            VarType::Boolean => "Boolean",
            VarType::Int16 => "Int16",
            VarType::Int32 | VarType::Pair => "Int32",
            VarType::Real => "Float32",
        };
        let start = match variable.ty {
            VarType::Boolean => "false",
            VarType::Int16 | VarType::Int32 | VarType::Pair | VarType::Real => "0",
        };
        let vr = device_vr(index);
        let name = &variable.name;
        let _ = match variable.causality {
            Causality::Input => writeln!(
                out,
                "    <{element} name=\"{name}\" valueReference=\"{vr}\" causality=\"input\" variability=\"discrete\" start=\"{start}\"/>"
            ),
            Causality::Output => writeln!(
                out,
                "    <{element} name=\"{name}\" valueReference=\"{vr}\" causality=\"output\" variability=\"discrete\"/>"
            ),
        };
    }
    let _ = writeln!(out, "  </ModelVariables>");
    let _ = writeln!(out, "  <ModelStructure>");
    let outputs: Vec<u32> = outputs(variables).map(device_vr).collect();
    for vr in &outputs {
        let _ = writeln!(out, "    <Output valueReference=\"{vr}\" dependencies=\"\"/>");
    }
    for vr in &outputs {
        let _ = writeln!(out, "    <InitialUnknown valueReference=\"{vr}\" dependencies=\"\"/>");
    }
    let _ = writeln!(out, "  </ModelStructure>");
    let _ = writeln!(out, "</fmiModelDescription>");
    out
}

fn outputs(variables: &[Variable]) -> impl Iterator<Item = usize> + '_ {
    variables
        .iter()
        .enumerate()
        .filter(|(_, variable)| variable.causality == Causality::Output)
        .map(|(index, _)| index)
}

fn fmi2(options: &FmuOptions, identifier: &str, token: &str, variables: &[Variable]) -> String {
    let period = period_seconds(options);
    let mut out = String::new();
    header(&mut out, "2.0", options, "guid", token);
    let _ = writeln!(
        out,
        "  <CoSimulation modelIdentifier=\"{identifier}\" canHandleVariableCommunicationStepSize=\"true\"\n    \
         canGetAndSetFMUstate=\"true\" canSerializeFMUstate=\"true\" canNotUseMemoryManagementFunctions=\"true\"/>"
    );
    let _ = writeln!(out, "  <DefaultExperiment startTime=\"0\" stepSize=\"{period}\"/>");
    let _ = writeln!(out, "  <ModelVariables>");
    // Index 1 is the scan period; devices follow from index 2.
    let _ = writeln!(
        out,
        "    <ScalarVariable name=\"scan_period\" valueReference=\"{VR_SCAN_PERIOD}\" causality=\"parameter\" \
         variability=\"fixed\" initial=\"exact\" description=\"seconds between scans\">\n      \
         <Real start=\"{period}\" min=\"0.001\" max=\"60\"/>\n    </ScalarVariable>"
    );
    for (index, variable) in variables.iter().enumerate() {
        let vr = device_vr(index);
        let name = &variable.name;
        // FMI 2.0 Integers are 32-bit: a word says its range.
        let (element, start) = match variable.ty {
            VarType::Boolean => ("Boolean", "start=\"false\""),
            VarType::Int16 => ("Integer", "start=\"0\" min=\"-32768\" max=\"32767\""),
            VarType::Int32 | VarType::Pair => ("Integer", "start=\"0\""),
            VarType::Real => ("Real", "start=\"0\""),
        };
        let range = match variable.ty {
            VarType::Int16 => " min=\"-32768\" max=\"32767\"",
            VarType::Boolean | VarType::Int32 | VarType::Pair | VarType::Real => "",
        };
        let _ = match variable.causality {
            Causality::Input => writeln!(
                out,
                "    <ScalarVariable name=\"{name}\" valueReference=\"{vr}\" causality=\"input\" variability=\"discrete\">\n      \
                 <{element} {start}/>\n    </ScalarVariable>"
            ),
            Causality::Output => writeln!(
                out,
                "    <ScalarVariable name=\"{name}\" valueReference=\"{vr}\" causality=\"output\" variability=\"discrete\" initial=\"calculated\">\n      \
                 <{element}{range}/>\n    </ScalarVariable>"
            ),
        };
    }
    let _ = writeln!(out, "  </ModelVariables>");
    let _ = writeln!(out, "  <ModelStructure>");
    // FMI 2.0 names variables by their 1-based place in ModelVariables.
    let places: Vec<usize> = outputs(variables).map(|index| index + 2).collect();
    if !places.is_empty() {
        let _ = writeln!(out, "    <Outputs>");
        for place in &places {
            let _ = writeln!(out, "      <Unknown index=\"{place}\" dependencies=\"\"/>");
        }
        let _ = writeln!(out, "    </Outputs>");
        let _ = writeln!(out, "    <InitialUnknowns>");
        for place in &places {
            let _ = writeln!(out, "      <Unknown index=\"{place}\" dependencies=\"\"/>");
        }
        let _ = writeln!(out, "    </InitialUnknowns>");
    }
    let _ = writeln!(out, "  </ModelStructure>");
    let _ = writeln!(out, "</fmiModelDescription>");
    out
}
