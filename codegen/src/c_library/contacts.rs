//! A robot's contacts in its C library: what each contact is (`P_contact_info`), and the
//! runtime's constrained functions assembled from the generated rows
//! (`P_constrained_forward_dynamics`, `P_impulse_dynamics`, `P_operational_space_inertia`).
//! The rows themselves (`contact_jacobian`, `contact_drift`, `contact_response`, the Delassus
//! matrix and the one-call rows) are entries of the table like any generated quantity. A robot without contacts has the same functions:
//! no contact, and `DYNGEN_ERROR_NOT_GENERATED` from the three solves.

use super::header::documented;
use super::table::reference_number;
use super::Library;
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

/// Contacts with the world: the anchors a stabilised solve takes, one each.
fn anchor_count(library: &Library) -> usize {
    library.contacts.iter().filter(|c| c.to.is_none()).count()
}

/// The `P_contact_info` table, `P_nc`, `P_contact_count` and the three solves.
pub(super) fn wrapper_items(library: &Library) -> TokenStream {
    let prefix = &library.prefix;
    let f = |name: &str| format_ident!("{prefix}_{name}");
    let [nc_fn, contact_count, contact_info] = ["nc", "contact_count", "contact_info"].map(f);
    let mut first_row = 0;
    let rows: Vec<TokenStream> = (library.contacts.iter())
        .map(|c| {
            let (frame, rows) = (usize(c.frame), usize(c.kind.rows()));
            let to = match c.to.map(usize) {
                Some(to) => quote!(#to),
                None => quote!(HELD_TO_WORLD),
            };
            let (first, reference) = (usize(first_row), reference_number(Some(c.reference)));
            first_row += c.kind.rows();
            quote!(ContactInfo { frame: #frame, to: #to, rows: #rows, first_row: #first, reference: #reference })
        })
        .collect();
    let (count, nc, anchors) = (
        usize(library.contacts.len()),
        usize(library.sizes.contact_rows),
        usize(anchor_count(library)),
    );
    let solves = match library.contacts.is_empty() {
        true => not_generated(library),
        false => solves(library),
    };
    quote! {
        /// Contact rows, and contacts.
        const NC: usize = #nc;
        const CONTACT_COUNT: usize = #count;
        /// Contacts with the world: the anchors of a stabilised solve.
        const ANCHORS: usize = #anchors;
        /// `DYNGEN_HELD_TO_WORLD`.
        const HELD_TO_WORLD: usize = usize::MAX;

        /// `dyngen_contact_info`: one contact.
        #[repr(C)]
        pub struct ContactInfo {
            pub frame: usize,
            pub to: usize,
            pub rows: usize,
            pub first_row: usize,
            pub reference: i32,
        }

        static CONTACTS: [ContactInfo; CONTACT_COUNT] = [#(#rows),*];

        /// Contact rows: the length of the forces and the rows of `J`.
        #[no_mangle]
        pub extern "C" fn #nc_fn() -> usize {
            NC
        }

        /// Contacts, in the order of their rows.
        #[no_mangle]
        pub extern "C" fn #contact_count() -> usize {
            CONTACTS.len()
        }

        /// Contact `contact`; null when out of range.
        #[no_mangle]
        pub extern "C" fn #contact_info(contact: usize) -> Option<&'static ContactInfo> {
            CONTACTS.get(contact)
        }

        /// `dyngen_contact_settings`: how a constrained solve runs.
        #[repr(C)]
        pub struct ContactSettings {
            pub mu: f64,
            pub max_iterations: usize,
            pub accuracy: f64,
            pub kp: f64,
            pub kd: f64,
            pub anchors: *const f64,
        }

        #solves
    }
}

fn usize(n: usize) -> Literal {
    Literal::usize_unsuffixed(n)
}

/// The three solves' symbols and parameters, with or without contacts.
fn solve_signatures(library: &Library) -> [(proc_macro2::Ident, TokenStream); 3] {
    let prefix = &library.prefix;
    let name = |name: &str| format_ident!("{prefix}_{name}");
    [
        (
            name("constrained_forward_dynamics"),
            quote! {
                q: *const f64,
                qd: *const f64,
                tau: *const f64,
                settings: *const ContactSettings,
                warm_start: *const f64,
                qdd: *mut f64,
                forces: *mut f64,
            },
        ),
        (
            name("impulse_dynamics"),
            quote!(q: *const f64, qd: *const f64, restitution: f64, mu: f64, qd_after: *mut f64, impulses: *mut f64),
        ),
        (
            name("operational_space_inertia"),
            quote!(q: *const f64, damping: f64, inertia: *mut f64),
        ),
    ]
}

/// The three solves of a robot without contacts.
fn not_generated(library: &Library) -> TokenStream {
    let [(forward, forward_parameters), (impulse, impulse_parameters), (inertia, inertia_parameters)] =
        solve_signatures(library);
    quote! {
        /// The robot has no contacts.
        #[no_mangle]
        pub extern "C" fn #forward(#forward_parameters) -> i32 {
            let _ = (q, qd, tau, settings, warm_start, qdd, forces, NC, ANCHORS, HELD_TO_WORLD);
            NOT_GENERATED
        }

        /// The robot has no contacts.
        #[no_mangle]
        pub extern "C" fn #impulse(#impulse_parameters) -> i32 {
            let _ = (q, qd, restitution, mu, qd_after, impulses);
            NOT_GENERATED
        }

        /// The robot has no contacts.
        #[no_mangle]
        pub extern "C" fn #inertia(#inertia_parameters) -> i32 {
            let _ = (q, damping, inertia);
            NOT_GENERATED
        }
    }
}

/// The runtime's constrained functions over the robot's `ContactDynamics`.
fn solves(library: &Library) -> TokenStream {
    let ty = format_ident!("{}", library.type_name);
    let [(forward, forward_parameters), (impulse, impulse_parameters), (inertia, inertia_parameters)] =
        solve_signatures(library);
    quote! {
        use dyngen_runtime::{ContactDynamics, ContactError, Pose, ProximalSettings, Stabilisation};

        __dyngen_comment!("The generated rows are the robot's, for the contacts the header lists.");
        const _: () = assert!(<robot::#ty as ContactDynamics<NV, NC>>::CONTACT_FRAMES.len() == CONTACT_COUNT);

        /// The status of a solve that gave no answer.
        fn contact_status(error: ContactError) -> i32 {
            __dyngen_comment!("Besides redundant rows, settings and restitutions: the anchors' count and the contacts' axes are the generated robot's, never wrong.");
            match error {
                ContactError::Redundant { .. } => REDUNDANT_CONTACTS,
                ContactError::Settings(_)
                | ContactError::Restitution(_)
                | ContactError::Anchors { .. }
                | ContactError::WorldReference(_) => CONTACT_SETTINGS,
            }
        }

        /// The anchors of a stabilised solve.
        ///
        /// # Safety
        /// `anchors` points to `12 · ANCHORS` readable doubles (it may be null when `ANCHORS`
        /// is 0: nothing is read).
        unsafe fn read_anchors(anchors: *const f64) -> [Pose; ANCHORS] {
            core::array::from_fn(|k| {
                __dyngen_comment!("SAFETY: anchor `k` lies within the `ANCHORS` the caller provides.");
                let [c0, c1, c2, translation] = unsafe { anchors.add(12 * k).cast::<[[f64; 3]; 4]>().read_unaligned() };
                Pose {
                    rotation: SMatrix::from([c0, c1, c2]),
                    translation: SVector::from(translation),
                }
            })
        }

        /// Constrained forward dynamics (the runtime's `constrained_forward_dynamics`): `q̈` and
        /// the contact forces with every contact held; exact without settings.
        ///
        /// # Safety
        /// `q` points to `NQ` readable doubles, `qd` and `tau` to `NV`, `qdd` to `NV` writable
        /// ones and `forces` to `NC`; `warm_start` is null or points to `NC` readable doubles;
        /// `settings` is null or points to a `ContactSettings` whose `anchors`, when `kp` or
        /// `kd` is not 0, points to `12 · ANCHORS` readable doubles. Outputs must not overlap
        /// each other (inputs are read before any output is written).
        #[no_mangle]
        pub unsafe extern "C" fn #forward(#forward_parameters) -> i32 {
            if q.is_null() || qd.is_null() || tau.is_null() || qdd.is_null() || forces.is_null() {
                return NULL_POINTER;
            }
            __dyngen_comment!("SAFETY: null, or a `ContactSettings` (the contract).");
            let settings = (!settings.is_null()).then(|| unsafe { settings.read_unaligned() });
            let proximal = settings.as_ref().map_or(ProximalSettings::default(), |s| ProximalSettings {
                mu: s.mu,
                max_iterations: s.max_iterations,
                accuracy: s.accuracy,
            });
            __dyngen_comment!("Stabilised when a gain is not 0 (zero gains ask for what no stabilisation does); a non-finite gain is refused by the solve.");
            let stabilised = settings.as_ref().filter(|s| s.kp != 0.0 || s.kd != 0.0);
            if stabilised.is_some_and(|s| ANCHORS > 0 && s.anchors.is_null()) {
                return NULL_POINTER;
            }
            __dyngen_comment!("SAFETY: `12 · ANCHORS` doubles when stabilised (the contract).");
            let anchors = stabilised.map(|s| (unsafe { read_anchors(s.anchors) }, s.kp, s.kd));
            let stabilisation = anchors.as_ref().map(|(anchors, kp, kd)| Stabilisation { anchors, kp: *kp, kd: *kd });
            let (mut copy0, mut copy1, mut copy2, mut copy3) = (MaybeUninit::uninit(), MaybeUninit::uninit(), MaybeUninit::uninit(), MaybeUninit::uninit());
            __dyngen_comment!("SAFETY: non-null, and the lengths of this function's contract.");
            let (q, qd, tau) = unsafe { (input::<NQ>(q, &mut copy0), input::<NV>(qd, &mut copy1), input::<NV>(tau, &mut copy2)) };
            __dyngen_comment!("SAFETY: null, or `NC` doubles (the contract).");
            let warm_start = (!warm_start.is_null()).then(|| unsafe { input::<NC>(warm_start, &mut copy3) });
            let t = match trig(q) {
                Ok(t) => t,
                Err(status) => return status,
            };
            match dyngen_runtime::constrained_forward_dynamics::<robot::#ty, NV, NC>(&t, qd, tau, stabilisation, &proximal, warm_start) {
                Ok(solved) => {
                    __dyngen_comment!("SAFETY: non-null, and `NV` and `NC` doubles (the contract).");
                    unsafe {
                        output(qdd, solved.acceleration);
                        output(forces, solved.forces);
                    }
                    OK
                }
                Err(error) => contact_status(error),
            }
        }

        /// The velocity just after every contact strikes and the impulses (the runtime's
        /// `impulse_dynamics`): `J q̇⁺ = −restitution · J q̇`, one solve damped by `mu`.
        ///
        /// # Safety
        /// `q` points to `NQ` readable doubles, `qd` to `NV`, `qd_after` to `NV` writable ones
        /// and `impulses` to `NC`; outputs must not overlap each other.
        #[no_mangle]
        pub unsafe extern "C" fn #impulse(#impulse_parameters) -> i32 {
            if q.is_null() || qd.is_null() || qd_after.is_null() || impulses.is_null() {
                return NULL_POINTER;
            }
            let (mut copy0, mut copy1) = (MaybeUninit::uninit(), MaybeUninit::uninit());
            __dyngen_comment!("SAFETY: non-null, and the lengths of this function's contract.");
            let (q, qd) = unsafe { (input::<NQ>(q, &mut copy0), input::<NV>(qd, &mut copy1)) };
            let t = match trig(q) {
                Ok(t) => t,
                Err(status) => return status,
            };
            match dyngen_runtime::impulse_dynamics::<robot::#ty, NV, NC>(&t, qd, restitution, mu) {
                Ok((after, impulse)) => {
                    __dyngen_comment!("SAFETY: non-null, and `NV` and `NC` doubles (the contract).");
                    unsafe {
                        output(qd_after, after);
                        output(impulses, impulse);
                    }
                    OK
                }
                Err(error) => contact_status(error),
            }
        }

        /// The contact rows' operational-space inertia `(J M⁻¹ Jᵀ + damping · I)⁻¹` (the
        /// runtime's `operational_space_inertia`).
        ///
        /// # Safety
        /// `q` points to `NQ` readable doubles, `inertia` to `NC · NC` writable ones.
        #[no_mangle]
        pub unsafe extern "C" fn #inertia(#inertia_parameters) -> i32 {
            if q.is_null() || inertia.is_null() {
                return NULL_POINTER;
            }
            let mut copy = MaybeUninit::uninit();
            __dyngen_comment!("SAFETY: non-null, and `NQ` doubles (the contract).");
            let q = unsafe { input::<NQ>(q, &mut copy) };
            let t = match trig(q) {
                Ok(t) => t,
                Err(status) => return status,
            };
            match dyngen_runtime::operational_space_inertia::<robot::#ty, NV, NC>(&t, damping) {
                Ok(value) => {
                    __dyngen_comment!("SAFETY: non-null, and `NC · NC` doubles (the contract).");
                    unsafe { output(inertia, value) };
                    OK
                }
                Err(error) => contact_status(error),
            }
        }
    }
}

/// The header's declarations of the contacts' functions.
pub(super) fn declarations(library: &Library) -> String {
    let p = &library.prefix;
    let pp = p.to_ascii_uppercase();
    let mut text = format!(
        r#"
/* Contacts (docs/contacts.md in dyngen's repository): the frames the description holds, to the
 * world or to another frame (a loop closure), in the order of their rows; {pp}_NC rows in all,
 * the length of the forces. A robot without contacts has none, and its three solves return
 * DYNGEN_ERROR_NOT_GENERATED. */
size_t {p}_nc(void);
size_t {p}_contact_count(void);
/* Contact `contact` (NULL when out of range; static). */
const dyngen_contact_info *{p}_contact_info(size_t contact);
"#
    );
    let mut errors = vec!["DYNGEN_ERROR_NULL_POINTER"];
    if library.sizes.floating {
        errors.push("DYNGEN_ERROR_NON_UNIT_QUATERNION");
    }
    errors.extend(["DYNGEN_ERROR_CONTACT_SETTINGS", "DYNGEN_ERROR_REDUNDANT_CONTACTS"]);
    let q = (
        "const double *",
        "q",
        "in",
        format!("{pp}_NQ doubles: the configuration"),
    );
    let doubles = "const double *";
    text += &documented(
        library,
        "constrained_forward_dynamics",
        &[
            "The acceleration q̈ (ν̇ on a floating base) and the contact forces with every contact \
             held (Pinocchio's constraintDynamics): D q̈ + C q̇ + g = tau + Jᵀ forces, J q̈ = \
             −drift (−drift − kp e − kd J q̇ when stabilised); the forces act on the robot, in \
             each contact's axes"
                .into(),
            "Exact without settings: the rows must be independent (else \
             DYNGEN_ERROR_REDUNDANT_CONTACTS: solve with mu > 0)"
                .into(),
        ],
        &[
            q.clone(),
            (doubles, "qd", "in", format!("{pp}_NV doubles: the velocity")),
            (
                doubles,
                "tau",
                "in",
                format!("{pp}_NV doubles: the generalised force"),
            ),
            (
                "const dyngen_contact_settings *",
                "settings",
                "in",
                format!(
                    "NULL: the exact solve; else the solve dyngen_contact_settings describes, \
                     stabilised towards {pp}_ANCHOR_COUNT anchors when kp or kd is not 0"
                ),
            ),
            (
                doubles,
                "warm_start",
                "in",
                format!(
                    "NULL, or {pp}_NC doubles: the forces the proximal iterations start from \
                     (the last tick's; it may be the forces array itself)"
                ),
            ),
            ("double *", "qdd", "out", format!("{pp}_NV doubles")),
            ("double *", "forces", "out", format!("{pp}_NC doubles")),
        ],
        &errors,
    );
    text += &documented(
        library,
        "impulse_dynamics",
        &[
            "The velocity just after every contact strikes, J qd_after = −restitution J qd, and \
           the impulses, D (qd_after − qd) = Jᵀ impulses (Pinocchio's impulseDynamics)"
                .into(),
        ],
        &[
            q.clone(),
            (
                doubles,
                "qd",
                "in",
                format!("{pp}_NV doubles: the velocity just before"),
            ),
            (
                "double",
                "restitution",
                "in",
                "in [0, 1]: 0 stops the contacts, 1 bounces them back".into(),
            ),
            (
                "double",
                "mu",
                "in",
                "the solve's damping, at least 0 (0: exact, independent rows)".into(),
            ),
            ("double *", "qd_after", "out", format!("{pp}_NV doubles")),
            (
                "double *",
                "impulses",
                "out",
                format!("{pp}_NC doubles (N·s; N·m·s for moments)"),
            ),
        ],
        &errors,
    );
    text += &documented(
        library,
        "operational_space_inertia",
        &["The contact rows' operational-space inertia (J D⁻¹ Jᵀ + damping I)⁻¹".into()],
        &[
            q,
            (
                "double",
                "damping",
                "in",
                "at least 0: keeps it finite near singular configurations (0: the exact one)".into(),
            ),
            (
                "double *",
                "inertia",
                "out",
                format!("{pp}_NC x {pp}_NC doubles, column-major"),
            ),
        ],
        &errors,
    );
    text
}

/// The contacts' sizes for the header: `(macro suffix, value, about)`.
pub(super) fn sizes(library: &Library) -> [(&'static str, usize, &'static str); 3] {
    [
        (
            "NC",
            library.sizes.contact_rows,
            "contact rows (0 without contacts)",
        ),
        (
            "CONTACT_COUNT",
            library.contacts.len(),
            "contacts, in the order of their rows",
        ),
        (
            "ANCHOR_COUNT",
            anchor_count(library),
            "contacts with the world: the anchors of a stabilised solve",
        ),
    ]
}
