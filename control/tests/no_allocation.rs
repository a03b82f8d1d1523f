//! A control tick allocates nothing: a counting global allocator sees no allocation while the
//! adaptive controller (with stiffness estimation) runs many ticks.

use dyngen_control::controller::Measurement;
use dyngen_control::sim::{start_posture, Demo, DemoOptions, RunKind};
use dyngen_generated::arm7;
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::JointTrig;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn a_control_tick_allocates_nothing() {
    let q0 = start_posture::<7>("arm7").expect("arm7 start posture");
    let d = Demo::<arm7::Base, 7, { arm7::BASE_PARAMETER_COUNT }>::new(
        DemoOptions {
            stiffness_estimation: Some((0.5, 20.0)),
            start_height: -0.001,
            ..DemoOptions::default()
        },
        q0,
    )
    .expect("valid demo");
    let mut c = d.controller(RunKind::Adaptive).expect("valid controller");
    let desired: Vec<_> = (0..200).map(|k| d.scenario.desired(k as f64 * 0.05)).collect();
    let force = d.plant.contact_force(&JointTrig::new(&q0));
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    let mut acc = 0.0;
    for (k, des) in desired.iter().enumerate() {
        let m = Measurement {
            q: q0 + SVector::from_element(1e-3 * k as f64),
            qd: SVector::from_element(0.01),
            force,
        };
        let out = c.tick(&m, des, 1e-3).expect("tick");
        acc += out.tau.sum();
    }
    let after = ALLOCATIONS.load(Ordering::SeqCst);
    assert!(acc.is_finite());
    assert_eq!(after - before, 0, "a control tick allocated");
}
