//! Which functions a robot is generated with: groups a user chooses by name (in a
//! description's `functions:`, with `Builder::functions`, or `dyngen gen --functions`), each
//! the functions of one trait of `dyngen-runtime`.

use std::fmt;

/// A group of generated functions, chosen together; each is one trait of `dyngen-runtime`
/// (on a floating base its floating form, [`FunctionGroup::floating_trait_name`]), and means
/// the same on fixed and floating bases.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum FunctionGroup {
    /// Pose, `J`, `J̇` of the end-effector (`Kinematics`). Always generated.
    Kinematics,
    /// `θ`, `D`, `C`, `g`, `τ`, the Slotine–Li torque (`RobotDynamics`). Always generated.
    Dynamics,
    /// The regressors `Y` (Slotine–Li and torque form) and their products `Y θ`, `Yᵀ r`
    /// (`Regressors`).
    Regressors,
    /// The base parameters `θ_b`, `Y_b` and its products, and the lane functions
    /// (`BaseParameters`, `LaneDynamics`). Needs `regressors`.
    BaseParameters,
    /// `q̈ = D⁻¹ (τ − C q̇ − g)` and `D⁻¹` (`ForwardDynamics`).
    ForwardDynamics,
    /// `∂τ/∂(q, q̇)` and `∂q̈/∂(q, q̇)` (`DynamicsDerivatives`).
    Derivatives,
    /// Pose, `J`, `J̇`, velocity and classical acceleration of every named frame (the
    /// end-effector and `frames:`) in the three reference frames (`FrameKinematics`, and with
    /// it `WrenchDynamics`: dynamics with external wrenches at those frames).
    Frames,
    /// The pieces of constrained dynamics for the frames `contacts:` holds to the world: their
    /// rows `J`, drift and `M⁻¹ Jᵀ` (`ContactDynamics`), from which the runtime assembles
    /// constrained forward dynamics, impacts and the operational-space inertia. Generated only
    /// for a robot with contacts; needs `forward_dynamics` and `frames`.
    Contacts,
}

/// The keyword that chooses every group (`functions: all`, `--functions all`).
pub const ALL_GROUPS: &str = "all";

/// Up to this many joints, [`Functions::default_for`] is every group; above it,
/// [`LARGE_ROBOT_DEFAULT`]. The regressors (with their base-parameter forms) and the derivatives
/// are the code that grows fastest with the robot: a 30-joint chain's regressors alone are
/// 58 MiB of Rust, and all its groups together take many minutes to compile, where kinematics,
/// dynamics, forward dynamics and frames are 20 MiB.
pub const EVERY_GROUP_BY_DEFAULT_UP_TO_DOF: usize = 12;

/// What a robot of more than [`EVERY_GROUP_BY_DEFAULT_UP_TO_DOF`] joints gets when its
/// description chooses nothing: what whole-body control and simulation call every tick. The
/// regressors, base parameters and derivatives (identification, adaptive control, optimal
/// control) are generated when chosen.
pub const LARGE_ROBOT_DEFAULT: [FunctionGroup; 5] = [
    FunctionGroup::Kinematics,
    FunctionGroup::Dynamics,
    FunctionGroup::ForwardDynamics,
    FunctionGroup::Frames,
    FunctionGroup::Contacts,
];

impl FunctionGroup {
    /// Every group, in the order of the generated module.
    pub const ALL: [FunctionGroup; 8] = [
        FunctionGroup::Kinematics,
        FunctionGroup::Dynamics,
        FunctionGroup::Regressors,
        FunctionGroup::BaseParameters,
        FunctionGroup::ForwardDynamics,
        FunctionGroup::Derivatives,
        FunctionGroup::Frames,
        FunctionGroup::Contacts,
    ];

    /// The name a description, the builder and the command line use, e.g. `forward_dynamics`.
    pub fn keyword(self) -> &'static str {
        match self {
            FunctionGroup::Kinematics => "kinematics",
            FunctionGroup::Dynamics => "dynamics",
            FunctionGroup::Regressors => "regressors",
            FunctionGroup::BaseParameters => "base_parameters",
            FunctionGroup::ForwardDynamics => "forward_dynamics",
            FunctionGroup::Derivatives => "derivatives",
            FunctionGroup::Frames => "frames",
            FunctionGroup::Contacts => "contacts",
        }
    }

    /// The group named `keyword`.
    pub fn from_keyword(keyword: &str) -> Option<FunctionGroup> {
        FunctionGroup::ALL.into_iter().find(|g| g.keyword() == keyword)
    }

    /// The `dyngen-runtime` trait whose methods the group's functions are.
    pub fn trait_name(self) -> &'static str {
        match self {
            FunctionGroup::Kinematics => "Kinematics",
            FunctionGroup::Dynamics => "RobotDynamics",
            FunctionGroup::Regressors => "Regressors",
            FunctionGroup::BaseParameters => "BaseParameters",
            FunctionGroup::ForwardDynamics => "ForwardDynamics",
            FunctionGroup::Derivatives => "DynamicsDerivatives",
            FunctionGroup::Frames => "FrameKinematics",
            FunctionGroup::Contacts => "ContactDynamics",
        }
    }

    /// The `dyngen-runtime` trait whose methods the group's functions are on a floating base;
    /// `None` for `kinematics`, whose end-effector functions a floating base has among its
    /// frames'.
    pub fn floating_trait_name(self) -> Option<&'static str> {
        match self {
            FunctionGroup::Kinematics => None,
            FunctionGroup::Dynamics => Some("FloatingBaseDynamics"),
            FunctionGroup::Regressors => Some("FloatingRegressors"),
            FunctionGroup::BaseParameters => Some("FloatingBaseParameters"),
            FunctionGroup::ForwardDynamics => Some("FloatingForwardDynamics"),
            FunctionGroup::Derivatives => Some("FloatingDynamicsDerivatives"),
            FunctionGroup::Frames => Some("FloatingFrameKinematics"),
            FunctionGroup::Contacts => Some("ContactDynamics"),
        }
    }

    /// Whether every generated robot has it (the other traits build on these two).
    pub fn is_always_generated(self) -> bool {
        matches!(self, FunctionGroup::Kinematics | FunctionGroup::Dynamics)
    }

    /// The groups it cannot be generated without.
    pub fn needs(self) -> &'static [FunctionGroup] {
        match self {
            FunctionGroup::BaseParameters => &[FunctionGroup::Regressors],
            FunctionGroup::Contacts => &[FunctionGroup::ForwardDynamics, FunctionGroup::Frames],
            _ => &[],
        }
    }

    /// `kinematics, dynamics, …`: every keyword, for messages.
    pub fn keywords() -> String {
        let all: Vec<&str> = FunctionGroup::ALL.iter().map(|g| g.keyword()).collect();
        all.join(", ")
    }
}

impl fmt::Display for FunctionGroup {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.keyword())
    }
}

/// The groups one robot is generated with: always kinematics and dynamics, plus the chosen ones.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Functions {
    chosen: [bool; FunctionGroup::ALL.len()],
}

impl Functions {
    /// Every group.
    pub fn all() -> Functions {
        Functions {
            chosen: [true; FunctionGroup::ALL.len()],
        }
    }

    /// What a robot of `dof` joints gets when its description chooses nothing: every group up
    /// to [`EVERY_GROUP_BY_DEFAULT_UP_TO_DOF`] joints, [`LARGE_ROBOT_DEFAULT`] above.
    pub fn default_for(dof: usize) -> Functions {
        match dof > EVERY_GROUP_BY_DEFAULT_UP_TO_DOF {
            true => Functions::with(&LARGE_ROBOT_DEFAULT).expect("needs nothing it lacks"),
            false => Functions::all(),
        }
    }

    /// Kinematics, dynamics and `groups`. An error names a group chosen without the one it
    /// needs.
    pub fn with(groups: &[FunctionGroup]) -> Result<Functions, String> {
        let mut chosen = [false; FunctionGroup::ALL.len()];
        for g in FunctionGroup::ALL.into_iter().filter(|g| g.is_always_generated()) {
            chosen[g as usize] = true;
        }
        for &g in groups {
            chosen[g as usize] = true;
        }
        let functions = Functions { chosen };
        for g in functions.groups() {
            if let Some(needed) = g.needs().iter().find(|n| !functions.contains(**n)) {
                return Err(format!(
                    "the group `{g}` needs `{needed}`: add `{needed}` to the functions"
                ));
            }
        }
        Ok(functions)
    }

    /// Parses keywords (`["regressors", "derivatives"]`, or [`ALL_GROUPS`] for every group);
    /// an unknown one is an error that lists the groups.
    pub fn from_keywords<'a>(keywords: impl IntoIterator<Item = &'a str>) -> Result<Functions, String> {
        let mut groups = Vec::new();
        for keyword in keywords {
            if keyword == ALL_GROUPS {
                return Ok(Functions::all());
            }
            match FunctionGroup::from_keyword(keyword) {
                Some(g) => groups.push(g),
                None => {
                    return Err(format!(
                        "unknown group of functions `{keyword}`: expected some of {}, or `{ALL_GROUPS}`",
                        FunctionGroup::keywords()
                    ))
                }
            }
        }
        Functions::with(&groups)
    }

    /// The same groups but `group` (which no other group may need).
    pub fn without(mut self, group: FunctionGroup) -> Functions {
        self.chosen[group as usize] = group.is_always_generated();
        self
    }

    /// Whether `group` is generated.
    pub fn contains(&self, group: FunctionGroup) -> bool {
        self.chosen[group as usize]
    }

    /// The generated groups, in module order.
    pub fn groups(&self) -> impl Iterator<Item = FunctionGroup> + '_ {
        FunctionGroup::ALL.into_iter().filter(|g| self.contains(*g))
    }
}

/// As a description writes it: `all` ([`ALL_GROUPS`]), or a list of group keywords
/// (`[regressors, forward_dynamics]`); an unknown keyword, or a group without the one it needs,
/// is an error.
impl<'de> serde::Deserialize<'de> for Functions {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        // A visitor, not a buffered `untagged` enum: the error then carries the place of the
        // value in the file.
        struct Written;
        impl<'de> serde::de::Visitor<'de> for Written {
            type Value = Functions;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "`{ALL_GROUPS}` or a list of groups of functions")
            }
            fn visit_str<E: serde::de::Error>(self, keyword: &str) -> Result<Functions, E> {
                Functions::from_keywords([keyword]).map_err(E::custom)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Functions, A::Error> {
                let mut keywords: Vec<String> = Vec::new();
                while let Some(keyword) = seq.next_element()? {
                    keywords.push(keyword);
                }
                Functions::from_keywords(keywords.iter().map(String::as_str))
                    .map_err(serde::de::Error::custom)
            }
        }
        deserializer.deserialize_any(Written)
    }
}

impl fmt::Display for Functions {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let groups: Vec<&str> = self.groups().map(FunctionGroup::keyword).collect();
        f.write_str(&groups.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keywords_round_trip_and_unknown_ones_list_the_groups() {
        for g in FunctionGroup::ALL {
            assert_eq!(FunctionGroup::from_keyword(g.keyword()), Some(g));
        }
        let e = Functions::from_keywords(["derivative"]).unwrap_err();
        assert!(e.contains("`derivative`") && e.contains("derivatives"), "{e}");
        assert_eq!(
            Functions::from_keywords(["regressors", ALL_GROUPS]),
            Ok(Functions::all())
        );
    }

    #[test]
    fn kinematics_and_dynamics_are_always_there_and_needs_are_checked() {
        let f = Functions::with(&[FunctionGroup::ForwardDynamics]).unwrap();
        let groups: Vec<FunctionGroup> = f.groups().collect();
        assert_eq!(
            groups,
            [
                FunctionGroup::Kinematics,
                FunctionGroup::Dynamics,
                FunctionGroup::ForwardDynamics
            ]
        );
        let e = Functions::with(&[FunctionGroup::BaseParameters]).unwrap_err();
        assert!(e.contains("`base_parameters` needs `regressors`"), "{e}");
        assert!(Functions::with(&[FunctionGroup::BaseParameters, FunctionGroup::Regressors]).is_ok());
    }

    #[test]
    fn large_robots_get_the_per_tick_groups_by_default() {
        assert_eq!(
            Functions::default_for(EVERY_GROUP_BY_DEFAULT_UP_TO_DOF),
            Functions::all()
        );
        let large = Functions::default_for(EVERY_GROUP_BY_DEFAULT_UP_TO_DOF + 1);
        for g in FunctionGroup::ALL {
            assert_eq!(large.contains(g), LARGE_ROBOT_DEFAULT.contains(&g), "{g}");
        }
    }
}
