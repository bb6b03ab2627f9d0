//! The FMI 3.0 `modelDescription.xml` of `PendulumFem3`, written from the same variable table as
//! the FMI 2.0 one: typed variables (`<Float64>`, `<Int32>`, `<Boolean>`), the model structure by
//! value reference, the capability flags of early return and event mode, and the instantiation
//! token (the FMI 2.0 GUID: a hash of the table's XML, so a binary refuses a description of another
//! table).

use std::fmt::Write as _;

use super::xml::{
    causality_attributes, depends_directly_on_tau, escape, format_start, guid, units_logs_and_experiment,
};
use super::{Causality, Kind, Role, MODEL_IDENTIFIER_FMI3, TIME_VR_FMI3, VARIABLES};

/// The complete FMI 3.0 `modelDescription.xml`.
pub fn model_description_fmi3() -> String {
    let mut x = String::new();
    x.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        x,
        "<fmiModelDescription fmiVersion=\"3.0\" modelName=\"{MODEL_IDENTIFIER_FMI3}\" instantiationToken=\"{}\" \
         description=\"Deformable hyperelastic pendulum (finite elements), driven by a torque at the pivot; wall \
         impacts as events\" generationTool=\"pendulum-fem-fmu {}\" variableNamingConvention=\"flat\">",
        guid(),
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        x,
        "  <CoSimulation modelIdentifier=\"{MODEL_IDENTIFIER_FMI3}\" needsExecutionTool=\"false\" \
         canBeInstantiatedOnlyOncePerProcess=\"false\" canGetAndSetFMUState=\"true\" canSerializeFMUState=\"true\" \
         providesDirectionalDerivatives=\"false\" providesAdjointDerivatives=\"false\" \
         providesPerElementDependencies=\"false\" canHandleVariableCommunicationStepSize=\"true\" \
         maxOutputDerivativeOrder=\"0\" providesIntermediateUpdate=\"false\" mightReturnEarlyFromDoStep=\"true\" \
         canReturnEarlyAfterIntermediateUpdate=\"false\" hasEventMode=\"true\" \
         providesEvaluateDiscreteStates=\"false\"/>"
    );
    x.push_str(&units_logs_and_experiment());
    x.push_str("  <ModelVariables>\n");
    // FMI 3.0 declares the independent variable
    let _ = writeln!(
        x,
        "    <Float64 name=\"time\" valueReference=\"{TIME_VR_FMI3}\" description=\"Simulation time\" \
         causality=\"independent\" variability=\"continuous\" unit=\"s\"/>"
    );
    for v in VARIABLES {
        let (causality, variability, initial) = causality_attributes(v);
        let tag = match v.kind {
            Kind::Real => "Float64",
            Kind::Integer => "Int32",
            Kind::Boolean => "Boolean",
        };
        let mut attrs = String::new();
        if let Some(s) = v.start {
            let _ = write!(attrs, " start=\"{}\"", format_start(v, s));
        }
        if let Some(u) = v.unit {
            let _ = write!(attrs, " unit=\"{u}\"");
        }
        let _ = writeln!(
            x,
            "    <{tag} name=\"{}\" valueReference=\"{}\" description=\"{}\" causality=\"{causality}\" \
             variability=\"{variability}\"{initial}{attrs}/>",
            v.name,
            v.vr,
            escape(v.description)
        );
    }
    x.push_str("  </ModelVariables>\n  <ModelStructure>\n");
    let tau = VARIABLES.iter().find(|v| v.role == Role::Tau).expect("tau").vr;
    let outputs = || VARIABLES.iter().filter(|v| v.causality == Causality::Output);
    for v in outputs() {
        let deps = if depends_directly_on_tau(v) {
            tau.to_string()
        } else {
            String::new()
        };
        let _ = writeln!(x, "    <Output valueReference=\"{}\" dependencies=\"{deps}\"/>", v.vr);
    }
    for v in outputs() {
        // the initial state (rigid acceleration and elastic equilibrium) includes the torque
        let _ = writeln!(
            x,
            "    <InitialUnknown valueReference=\"{}\" dependencies=\"{tau}\"/>",
            v.vr
        );
    }
    x.push_str("  </ModelStructure>\n</fmiModelDescription>\n");
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fmi3_description_declares_every_variable_once_with_its_type_and_the_discrete_outputs() {
        let xml = model_description_fmi3();
        for v in VARIABLES {
            assert_eq!(xml.matches(&format!(" name=\"{}\"", v.name)).count(), 1, "{}", v.name);
        }
        for name in ["contact_count", "impact"] {
            let line = xml.lines().find(|l| l.contains(&format!("name=\"{name}\""))).unwrap();
            assert!(line.contains("variability=\"discrete\""), "{line}");
        }
        assert!(xml.contains("<Int32 name=\"contact_count\""));
        assert!(xml.contains("<Boolean name=\"impact\""));
        assert!(xml.contains(&format!("instantiationToken=\"{}\"", guid())));
    }
}
