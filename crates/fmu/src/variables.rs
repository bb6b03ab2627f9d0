//! The FMU's variables: one table, [`VARIABLES`], from which `modelDescription.xml` is generated
//! ([`model_description`]) and which the C interface reads (value references, types, starts, what
//! each parameter sets in the configuration). Nothing about a variable is written twice.
//!
//! Parameters that name a configuration key ([`Role::Config`]) are applied with the CLI's
//! `--set key=value` mechanism ([`pendulum_fem_core::Config::load`]), so they are checked exactly like
//! the CLI's values and their defaults are the CLI's (a test compares every start with
//! [`pendulum_fem_core::Config::default`]).

mod xml;
mod xml3;

pub use xml::{guid, model_description};
pub use xml3::model_description_fmi3;

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
    /// `model.kind`: 0 the full body, 1 the reduced one.
    ModelKind,
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
        name: "model_kind",
        vr: 44,
        kind: Kind::Integer,
        causality: Causality::Parameter,
        unit: None,
        start: Some(0.0),
        description: "The pendulum: 0 the full finite-element body, 1 the reduced body (its rotation and elastic modes in a floating frame; small strains, far faster)",
        role: Role::ModelKind,
    },
    integer(
        "modes",
        45,
        8.0,
        "Fixed-frame normal modes of the reduced body (1 to 50; its static correction modes come on top)",
        "model.modes",
    ),
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

/// The model identifier of the FMI 3.0 FMU: `binaries/x86_64-linux/PendulumFem3.so`.
pub const MODEL_IDENTIFIER_FMI3: &str = "PendulumFem3";

/// The value reference of the independent variable `time` of the FMI 3.0 FMU (FMI 3.0 declares
/// it; it is not in [`VARIABLES`], whose value references are all below it).
pub const TIME_VR_FMI3: u32 = 99;

/// The variable with value reference `vr` of base type `kind`.
pub fn lookup(vr: u32, kind: Kind) -> Option<(usize, &'static Variable)> {
    VARIABLES.iter().enumerate().find(|(_, v)| v.vr == vr && v.kind == kind)
}

/// The variable named `name`.
pub fn by_name(name: &str) -> Option<&'static Variable> {
    VARIABLES.iter().find(|v| v.name == name)
}
