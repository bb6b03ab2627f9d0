//! `modelDescription.xml` written from the variable table: units, log categories, the variables,
//! the model structure, and the GUID (a hash of that text) that ties a binary to its description.

use std::fmt::Write as _;

use super::{Causality, Kind, Output, Role, Variable, MODEL_IDENTIFIER, VARIABLES};
use pendulum_fem_core::store::hash::{fnv1a, fnv1a_from};

/// SI base-unit exponents `(kg, m, s, rad)` of the units the table uses.
fn base_units(unit: &str) -> [i32; 4] {
    match unit {
        "rad" => [0, 0, 0, 1],
        "rad/s" => [0, 0, -1, 1],
        "rad/s2" => [0, 0, -2, 1],
        "m" => [0, 1, 0, 0],
        "s" => [0, 0, 1, 0],
        "N" => [1, 1, -2, 0],
        "N.m" | "J" => [1, 2, -2, 0],
        "Pa" => [1, -1, -2, 0],
        "kg/m3" => [1, -3, 0, 0],
        "N/m3" => [1, -2, -2, 0],
        "m/s2" => [0, 1, -2, 0],
        other => panic!("unit {other} has no base units in variables::base_units"),
    }
}

/// Start value as the XML writes it.
pub(super) fn format_start(v: &Variable, start: f64) -> String {
    match v.kind {
        Kind::Real => format!("{start:?}"),
        Kind::Integer => format!("{}", start as i64),
        Kind::Boolean => (start != 0.0).to_string(),
    }
}

/// The 1-based index of the input `tau` in `<ModelVariables>`.
pub(super) fn tau_index() -> usize {
    VARIABLES
        .iter()
        .position(|v| v.role == Role::Tau)
        .expect("tau is in the table")
        + 1
}

/// The causality, variability and `initial` attribute (with its leading space, or empty) of `v`.
pub(super) fn causality_attributes(v: &Variable) -> (&'static str, &'static str, &'static str) {
    match (v.causality, v.kind) {
        (Causality::Parameter, _) => ("parameter", "fixed", " initial=\"exact\""),
        (Causality::Input, _) => ("input", "continuous", ""),
        (Causality::Output, Kind::Real) => ("output", "continuous", " initial=\"calculated\""),
        (Causality::Output, _) => ("output", "discrete", " initial=\"calculated\""),
    }
}

/// Whether the output `v` depends on the input `tau` directly (within a step): only the
/// acceleration feels the torque without a step; the rest follow it through the state.
pub(super) fn depends_directly_on_tau(v: &Variable) -> bool {
    v.role == Role::Output(Output::Alpha)
}

/// `<UnitDefinitions>`, `<LogCategories>` and `<DefaultExperiment>`: the same in the FMI 2.0 and
/// the FMI 3.0 model description.
pub(super) fn units_logs_and_experiment() -> String {
    let mut units: Vec<&str> = VARIABLES.iter().filter_map(|v| v.unit).collect();
    units.sort_unstable();
    units.dedup();
    let mut x = String::new();
    x.push_str("  <UnitDefinitions>\n");
    for u in units {
        let [kg, m, s, rad] = base_units(u);
        let mut attrs = String::new();
        for (name, e) in [("kg", kg), ("m", m), ("s", s), ("rad", rad)] {
            if e != 0 {
                let _ = write!(attrs, " {name}=\"{e}\"");
            }
        }
        let _ = writeln!(x, "    <Unit name=\"{u}\">\n      <BaseUnit{attrs}/>\n    </Unit>");
    }
    x.push_str("  </UnitDefinitions>\n");
    x.push_str("  <LogCategories>\n");
    x.push_str("    <Category name=\"logStatusError\" description=\"Errors: invalid parameters, failed steps\"/>\n");
    x.push_str("    <Category name=\"logStatusWarning\" description=\"Warnings\"/>\n");
    x.push_str("    <Category name=\"logAll\" description=\"Everything, including the set-up of the model\"/>\n");
    x.push_str("  </LogCategories>\n");
    x.push_str("  <DefaultExperiment startTime=\"0\" stopTime=\"1\" stepSize=\"0.01\"/>\n");
    x
}

/// The `<ModelVariables>`, `<UnitDefinitions>` and `<ModelStructure>` content: everything that the
/// GUID covers.
fn body() -> String {
    let mut x = units_logs_and_experiment();
    x.push_str("  <ModelVariables>\n");
    for (i, v) in VARIABLES.iter().enumerate() {
        let (causality, variability, initial) = causality_attributes(v);
        let _ = writeln!(
            x,
            "    <!-- index {} -->\n    <ScalarVariable name=\"{}\" valueReference=\"{}\" description=\"{}\" \
             causality=\"{causality}\" variability=\"{variability}\"{initial}>",
            i + 1,
            v.name,
            v.vr,
            escape(v.description)
        );
        let tag = match v.kind {
            Kind::Real => "Real",
            Kind::Integer => "Integer",
            Kind::Boolean => "Boolean",
        };
        let mut attrs = String::new();
        if let Some(u) = v.unit {
            let _ = write!(attrs, " unit=\"{u}\"");
        }
        if let Some(s) = v.start {
            let _ = write!(attrs, " start=\"{}\"", format_start(v, s));
        }
        let _ = writeln!(x, "      <{tag}{attrs}/>\n    </ScalarVariable>");
    }
    x.push_str("  </ModelVariables>\n");
    x.push_str("  <ModelStructure>\n    <Outputs>\n");
    let tau = tau_index();
    let outputs: Vec<(usize, &Variable)> = VARIABLES
        .iter()
        .enumerate()
        .filter(|(_, v)| v.causality == Causality::Output)
        .map(|(i, v)| (i + 1, v))
        .collect();
    for &(index, v) in &outputs {
        let deps = if depends_directly_on_tau(v) {
            tau.to_string()
        } else {
            String::new()
        };
        let _ = writeln!(x, "      <Unknown index=\"{index}\" dependencies=\"{deps}\"/>");
    }
    x.push_str("    </Outputs>\n    <InitialUnknowns>\n");
    for &(index, _) in &outputs {
        // the initial state (rigid acceleration and elastic equilibrium) includes the torque
        let _ = writeln!(x, "      <Unknown index=\"{index}\" dependencies=\"{tau}\"/>");
    }
    x.push_str("    </InitialUnknowns>\n  </ModelStructure>\n");
    x
}

pub(super) fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The GUID: FNV-1a hashes of the variable table's XML, formatted as a UUID. A changed table gives
/// a new GUID, and an FMU binary refuses a model description of another table.
pub fn guid() -> String {
    let text = body();
    let h1 = fnv1a(text.as_bytes());
    let h2 = fnv1a_from(text.as_bytes(), h1);
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        h1 >> 32,
        (h1 >> 16) & 0xffff,
        h1 & 0xffff,
        h2 >> 48,
        h2 & 0xffff_ffff_ffff
    )
}

/// The complete `modelDescription.xml`.
pub fn model_description() -> String {
    let mut x = String::new();
    x.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        x,
        "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"{MODEL_IDENTIFIER}\" guid=\"{}\" \
         description=\"Deformable hyperelastic pendulum (finite elements), driven by a torque at the pivot\" \
         generationTool=\"pendulum-fem-fmu {}\" variableNamingConvention=\"flat\" numberOfEventIndicators=\"0\">",
        guid(),
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        x,
        "  <CoSimulation modelIdentifier=\"{MODEL_IDENTIFIER}\" needsExecutionTool=\"false\" \
         canHandleVariableCommunicationStepSize=\"true\" canInterpolateInputs=\"false\" \
         maxOutputDerivativeOrder=\"0\" \
         canBeInstantiatedOnlyOncePerProcess=\"false\" canNotUseMemoryManagementFunctions=\"true\" \
         canGetAndSetFMUstate=\"true\" canSerializeFMUstate=\"true\" providesDirectionalDerivative=\"false\"/>"
    );
    x.push_str(&body());
    x.push_str("</fmiModelDescription>\n");
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_references_are_unique_and_every_unit_has_base_units() {
        for (i, a) in VARIABLES.iter().enumerate() {
            for b in &VARIABLES[i + 1..] {
                assert_ne!(a.vr, b.vr, "{} and {}", a.name, b.name);
                assert_ne!(a.name, b.name);
            }
            if let Some(u) = a.unit {
                base_units(u);
            }
        }
    }

    #[test]
    fn alpha_is_the_only_output_with_a_direct_dependency_on_tau() {
        let xml = model_description();
        let alpha = VARIABLES.iter().position(|v| v.name == "alpha").unwrap() + 1;
        let outputs = xml
            .split("<Outputs>")
            .nth(1)
            .unwrap()
            .split("</Outputs>")
            .next()
            .unwrap();
        for line in outputs.lines().filter(|l| l.contains("<Unknown")) {
            let direct = line.contains(&format!("index=\"{alpha}\""));
            assert_eq!(line.contains("dependencies=\"1\""), direct, "{line}");
        }
    }
}
