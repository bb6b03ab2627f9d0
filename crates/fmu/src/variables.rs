//! The FMU's variables: one table, [`VARIABLES`], from which `modelDescription.xml` is generated
//! ([`model_description`]) and which the C interface reads (value references, types, starts, what
//! each parameter sets in the configuration). Nothing about a variable is written twice.
//!
//! Parameters that name a configuration key ([`Role::Config`]) are applied with the CLI's
//! `--set key=value` mechanism ([`pendulum_fem_core::Config::load`]), so they are checked exactly like
//! the CLI's values and their defaults are the CLI's (a test compares every start with
//! [`pendulum_fem_core::Config::default`]).

use std::fmt::Write as _;

/// The FMI base type of a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `fmi2Real`.
    Real,
    /// `fmi2Integer`.
    Integer,
    /// `fmi2Boolean`.
    Boolean,
}

/// The FMI causality of a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    /// Fixed before the simulation starts (`variability = "fixed"`).
    Parameter,
    /// Set by the master between steps.
    Input,
    /// Computed by the FMU.
    Output,
}

/// The outputs, by meaning.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Output {
    /// Proxy angle θ, unwrapped \[rad\].
    Theta,
    /// Best-fit angular velocity \[rad/s\].
    Omega,
    /// Best-fit angular acceleration \[rad/s²\].
    Alpha,
    /// Distance of the head from the wall face \[m\].
    Gap,
    /// Force of the wall on the head \[N\].
    ContactForce,
    /// Impacts so far.
    ContactCount,
    /// An impact started during the last step.
    Impact,
    /// Kinetic + strain + gravitational energy \[J\].
    TotalEnergy,
}

/// What a variable stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// A configuration key, set by name (`section.key`).
    Config(&'static str),
    /// The initial angle in radians (the configuration's `initial.angle_deg` is in degrees).
    ThetaStart,
    /// The wall: 0 none, 1 rigid, 2 deformable (`wall.kind`).
    WallKind,
    /// `solver.max_cutbacks`: −1 for `"auto"`, otherwise the count.
    MaxCutbacks,
    /// The largest internal step of `fmi2DoStep` \[s\].
    MaxInternalStep,
    /// The actuator torque input \[N m\].
    Tau,
    /// An output.
    Output(Output),
}

/// One scalar variable.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Variable {
    /// Name (flat naming convention).
    pub name: &'static str,
    /// Value reference, unique over all types.
    pub vr: u32,
    /// Base type.
    pub kind: Kind,
    /// Causality.
    pub causality: Causality,
    /// Unit (declared in `<UnitDefinitions>`), `None` for dimensionless values.
    pub unit: Option<&'static str>,
    /// Start value of parameters and inputs (Integer and Boolean as 0/1 integers).
    pub start: Option<f64>,
    /// One-line description.
    pub description: &'static str,
    /// What it stands for.
    pub role: Role,
}

const fn real(
    name: &'static str,
    vr: u32,
    unit: Option<&'static str>,
    start: f64,
    description: &'static str,
    role: Role,
) -> Variable {
    Variable {
        name,
        vr,
        kind: Kind::Real,
        causality: Causality::Parameter,
        unit,
        start: Some(start),
        description,
        role,
    }
}

const fn integer(name: &'static str, vr: u32, start: f64, description: &'static str, key: &'static str) -> Variable {
    Variable {
        name,
        vr,
        kind: Kind::Integer,
        causality: Causality::Parameter,
        unit: None,
        start: Some(start),
        description,
        role: Role::Config(key),
    }
}

const fn output(
    name: &'static str,
    vr: u32,
    kind: Kind,
    unit: Option<&'static str>,
    description: &'static str,
    out: Output,
) -> Variable {
    Variable {
        name,
        vr,
        kind,
        causality: Causality::Output,
        unit,
        start: None,
        description,
        role: Role::Output(out),
    }
}

/// The variables, in the order of `<ModelVariables>` (the 1-based position is the index that
/// `<ModelStructure>` refers to).
pub const VARIABLES: &[Variable] = &[
    Variable {
        name: "tau",
        vr: 0,
        kind: Kind::Real,
        causality: Causality::Input,
        unit: Some("N.m"),
        start: Some(0.0),
        description: "Actuator torque at the pivot, counter-clockwise positive (held over each step)",
        role: Role::Tau,
    },
    output(
        "theta",
        1,
        Kind::Real,
        Some("rad"),
        "Proxy angle from hanging down, counter-clockwise, unwrapped",
        Output::Theta,
    ),
    output(
        "omega",
        2,
        Kind::Real,
        Some("rad/s"),
        "Best-fit angular velocity",
        Output::Omega,
    ),
    output(
        "alpha",
        3,
        Kind::Real,
        Some("rad/s2"),
        "Best-fit angular acceleration (depends on tau)",
        Output::Alpha,
    ),
    output(
        "gap",
        4,
        Kind::Real,
        Some("m"),
        "Smallest x of the head minus the wall face x (negative: penetration)",
        Output::Gap,
    ),
    output(
        "contact_force",
        5,
        Kind::Real,
        Some("N"),
        "Force of the wall on the head",
        Output::ContactForce,
    ),
    output(
        "contact_count",
        6,
        Kind::Integer,
        None,
        "Impacts of the head on the wall so far",
        Output::ContactCount,
    ),
    output(
        "impact",
        7,
        Kind::Boolean,
        None,
        "True during the step an impact started",
        Output::Impact,
    ),
    output(
        "total_energy",
        8,
        Kind::Real,
        Some("J"),
        "Kinetic + strain + gravitational energy",
        Output::TotalEnergy,
    ),
    real(
        "theta_start",
        20,
        Some("rad"),
        0.3490658503988659,
        "Initial angle from hanging down (20 deg)",
        Role::ThetaStart,
    ),
    real(
        "omega_start",
        21,
        Some("rad/s"),
        0.0,
        "Initial angular velocity",
        Role::Config("initial.angular_velocity"),
    ),
    real(
        "youngs_modulus",
        22,
        Some("Pa"),
        2.1e11,
        "Young's modulus",
        Role::Config("material.youngs_modulus"),
    ),
    real(
        "poisson_ratio",
        23,
        None,
        0.3,
        "Poisson's ratio (0 to 0.5 for the neo-Hookean law)",
        Role::Config("material.poisson_ratio"),
    ),
    real(
        "density",
        24,
        Some("kg/m3"),
        7800.0,
        "Mass density",
        Role::Config("material.density"),
    ),
    real(
        "thickness",
        25,
        Some("m"),
        0.01,
        "Out-of-plane thickness",
        Role::Config("geometry.thickness"),
    ),
    real(
        "gravity",
        26,
        Some("m/s2"),
        9.81,
        "Gravitational acceleration along -y (0: none)",
        Role::Config("gravity.g"),
    ),
    real(
        "rod_half_width",
        27,
        Some("m"),
        0.015,
        "Half-width of the rod",
        Role::Config("geometry.rod_half_width"),
    ),
    real(
        "head_radius",
        28,
        Some("m"),
        0.06,
        "Outer radius of the head",
        Role::Config("geometry.head_radius"),
    ),
    real(
        "hole_radius",
        29,
        Some("m"),
        0.03,
        "Radius of the hole in the head (0: none)",
        Role::Config("geometry.hole_radius"),
    ),
    real(
        "head_center_distance",
        30,
        Some("m"),
        0.24,
        "Distance from the pivot to the head centre",
        Role::Config("geometry.head_center_distance"),
    ),
    real(
        "mesh_max_size",
        31,
        Some("m"),
        0.03,
        "Largest element size",
        Role::Config("mesh.max_size"),
    ),
    real(
        "mesh_refine",
        32,
        None,
        1.0,
        "Divides every mesh size (0.1 to 100)",
        Role::Config("mesh.refine"),
    ),
    real(
        "dissipation",
        33,
        None,
        0.0,
        "Numerical dissipation of the energy-momentum scheme (0 to <1)",
        Role::Config("time.dissipation"),
    ),
    real(
        "solver_tolerance",
        34,
        Some("J"),
        1e-6,
        "Newton tolerance on the energy norm of the update",
        Role::Config("solver.tolerance"),
    ),
    real(
        "wall_x",
        35,
        Some("m"),
        -0.06,
        "x of the wall face (the hanging head touches it); also the plane of gap without a wall",
        Role::Config("wall.x"),
    ),
    real(
        "contact_stiffness",
        37,
        Some("N/m3"),
        2e10,
        "Contact pressure per unit penetration (energy k g^2/2 per unit area)",
        Role::Config("contact.stiffness"),
    ),
    real(
        "max_internal_step",
        36,
        Some("s"),
        0.01,
        "Largest internal step of a communication step (the CLI's dt)",
        Role::MaxInternalStep,
    ),
    integer(
        "mesh_order",
        40,
        2.0,
        "Geometric order of the elements: 1 straight, 2 curved",
        "mesh.order",
    ),
    integer(
        "solver_max_iterations",
        41,
        40.0,
        "Newton iterations allowed per step",
        "solver.max_iterations",
    ),
    Variable {
        name: "wall_kind",
        vr: 43,
        kind: Kind::Integer,
        causality: Causality::Parameter,
        unit: None,
        start: Some(0.0),
        description: "The wall: 0 none, 1 rigid (the half-plane x <= wall_x), 2 the tutorial's deformable block",
        role: Role::WallKind,
    },
    Variable {
        name: "solver_max_cutbacks",
        vr: 42,
        kind: Kind::Integer,
        causality: Causality::Parameter,
        unit: None,
        start: Some(-1.0),
        description: "Times a failing step may be halved, 0 to 30; -1 (auto): down to the mesh's wave time",
        role: Role::MaxCutbacks,
    },
];

/// The model identifier: the shared object is `binaries/linux64/PendulumFem.so`.
pub const MODEL_IDENTIFIER: &str = "PendulumFem";

/// The variable with value reference `vr` of base type `kind`.
pub fn lookup(vr: u32, kind: Kind) -> Option<(usize, &'static Variable)> {
    VARIABLES.iter().enumerate().find(|(_, v)| v.vr == vr && v.kind == kind)
}

/// The variable named `name`.
pub fn by_name(name: &str) -> Option<&'static Variable> {
    VARIABLES.iter().find(|v| v.name == name)
}

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
fn format_start(v: &Variable, start: f64) -> String {
    match v.kind {
        Kind::Real => format!("{start:?}"),
        Kind::Integer => format!("{}", start as i64),
        Kind::Boolean => (start != 0.0).to_string(),
    }
}

/// The 1-based index of the input `tau` in `<ModelVariables>`.
fn tau_index() -> usize {
    VARIABLES
        .iter()
        .position(|v| v.role == Role::Tau)
        .expect("tau is in the table")
        + 1
}

/// The `<ModelVariables>`, `<UnitDefinitions>` and `<ModelStructure>` content: everything that the
/// GUID covers.
fn body() -> String {
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
    x.push_str("  <ModelVariables>\n");
    for (i, v) in VARIABLES.iter().enumerate() {
        let (causality, variability, initial) = match (v.causality, v.kind) {
            (Causality::Parameter, _) => ("parameter", "fixed", " initial=\"exact\""),
            (Causality::Input, _) => ("input", "continuous", ""),
            (Causality::Output, Kind::Real) => ("output", "continuous", " initial=\"calculated\""),
            (Causality::Output, _) => ("output", "discrete", " initial=\"calculated\""),
        };
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
        // only the acceleration feels the torque without a step; the rest follow it through the state
        let deps = if v.role == Role::Output(Output::Alpha) {
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

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The GUID: FNV-1a hashes of the variable table's XML, formatted as a UUID. A changed table gives
/// a new GUID, and an FMU binary refuses a model description of another table.
pub fn guid() -> String {
    let text = body();
    let h1 = fnv1a(text.as_bytes(), 0xcbf2_9ce4_8422_2325);
    let h2 = fnv1a(text.as_bytes(), h1);
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        h1 >> 32,
        (h1 >> 16) & 0xffff,
        h1 & 0xffff,
        h2 >> 48,
        h2 & 0xffff_ffff_ffff
    )
}

/// 64-bit FNV-1a of `bytes` continued from `seed` (the offset basis `0xcbf2_9ce4_8422_2325` starts
/// a new hash).
pub(crate) fn fnv1a(bytes: &[u8], seed: u64) -> u64 {
    bytes
        .iter()
        .fold(seed, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3))
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
