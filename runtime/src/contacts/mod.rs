//! Frames held to the world by rigid contacts: what a contact is, how far a held frame has
//! drifted from its anchor, the solve shared by constrained forward dynamics, impacts and the
//! operational-space inertia, and the trait a generated robot with contacts implements.

mod dense;
mod derivatives;
mod kind;
mod placement;
mod robot;
mod solve;
mod system;

pub use derivatives::{
    assemble_derivatives, constrained_forward_dynamics_derivatives, ConstrainedDerivatives,
};
pub use kind::ContactKind;
pub use placement::placement_error;
pub use robot::{constrained_forward_dynamics, impulse_dynamics, operational_space_inertia, ContactDynamics};
pub use solve::{
    contact_inertia, delassus_inertia, solve_contacts, solve_contacts_with_delassus, ContactError,
    ContactSolution, ProximalSettings, Stabilisation,
};
pub use system::{ContactInertia, ContactMatrices, ContactStep, ContactSystem};
