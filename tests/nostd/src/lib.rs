//! Generated dynamics in a `#![no_std]` crate: what an embedded controller links.

#![no_std]

#[path = "../../../generated/src/arm7.rs"]
#[rustfmt::skip]
#[allow(clippy::all)]
pub mod arm7;

use arm7::{Arm7, JointVector};
use dyngen_runtime::prelude::*;

/// Gravity compensation plus the Slotine–Li torque of a tick: `D a + C v + g`.
#[no_mangle]
pub fn arm7_control_torque(q: &[f64; 7], qd: &[f64; 7], a: &[f64; 7]) -> [f64; 7] {
    let t = JointTrig::new(&JointVector::from(*q));
    let qd = JointVector::from(*qd);
    let tau = Arm7::slotine_li(&t, &qd, &qd, &JointVector::from(*a));
    tau.into()
}

/// Gravity torques through the base regressor and the base parameters.
#[no_mangle]
pub fn arm7_base_torque(q: &[f64; 7]) -> [f64; 7] {
    let t = JointTrig::new(&JointVector::from(*q));
    let z = JointVector::zeros();
    let theta_b = Arm7::base_parameters(&Arm7::parameters());
    (Arm7::base_regressor(&t, &z, &z, &z) * theta_b).into()
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {}
}
