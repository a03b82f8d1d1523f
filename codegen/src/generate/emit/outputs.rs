//! The result of a generated function: its type, the zero a result written in place starts
//! from, the value built from outputs, and where each output goes when it is written in place
//! ([`OutputSlots`]).

use super::plan::{Form, Plan};
use super::sizes::Sizes;
use crate::generate::quantities::Shape;
use crate::generate::trace::Quantity;
use crate::symbolic::{Graph, Id, Node};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};
use std::collections::HashMap;

/// The type `q` returns in `form`: a lane function's in its lane type `L`.
pub(super) fn result_type(q: &Quantity, form: Form) -> TokenStream {
    match (form, q.shape) {
        (Form::Lanes, Shape::Vector(len)) => {
            let len = Literal::usize_unsuffixed(len);
            quote!([L; #len])
        }
        (Form::Lanes, Shape::Matrix(r, c)) => {
            let (r, c) = (Literal::usize_unsuffixed(r), Literal::usize_unsuffixed(c));
            quote!([[L; #r]; #c])
        }
        (Form::Lanes, _) => unreachable!("only vectors and matrices have a lane form"),
        (Form::Scalar, shape) => match shape {
            Shape::Vector(len) => {
                let len = Literal::usize_unsuffixed(len);
                quote!(SVector<f64, #len>)
            }
            Shape::Matrix(r, c) => {
                let (r, c) = (Literal::usize_unsuffixed(r), Literal::usize_unsuffixed(c));
                quote!(SMatrix<f64, #r, #c>)
            }
            Shape::Pose => quote!(Pose),
            Shape::Kinematics(n) => {
                let n = Literal::usize_unsuffixed(n);
                quote!((Pose, SMatrix<f64, 6, #n>, SMatrix<f64, 6, #n>))
            }
            Shape::MatrixPair(r, c) => {
                let (r, c) = (Literal::usize_unsuffixed(r), Literal::usize_unsuffixed(c));
                quote!((SMatrix<f64, #r, #c>, SMatrix<f64, #r, #c>))
            }
            Shape::VectorPair(n, m) => {
                let (n, m) = (Literal::usize_unsuffixed(n), Literal::usize_unsuffixed(m));
                quote!((SVector<f64, #n>, SVector<f64, #m>))
            }
            Shape::ContactMatrices(n, c) => {
                let (n, c) = (Literal::usize_unsuffixed(n), Literal::usize_unsuffixed(c));
                quote!(ContactMatrices<#n, #c>)
            }
            Shape::ContactSystem(n, c) => {
                let (n, c) = (Literal::usize_unsuffixed(n), Literal::usize_unsuffixed(c));
                quote!(ContactSystem<#n, #c>)
            }
            Shape::ContactStep(n, c) => {
                let (n, c) = (Literal::usize_unsuffixed(n), Literal::usize_unsuffixed(c));
                quote!(ContactStep<#n, #c>)
            }
            Shape::ContactInertia(c) => {
                let c = Literal::usize_unsuffixed(c);
                quote!(ContactInertia<#c>)
            }
        },
    }
}

/// Whether output `id` is zero in every state: never written, left as the result was filled.
pub(super) fn is_structural_zero(g: &Graph, id: Id) -> bool {
    g.constant_value(id) == Some(0.0) || g.node(id) == Node::LaneZero
}

/// The result built from its outputs `atoms` (a function not written in place).
pub(super) fn result_value(q: &Quantity, form: Form, atoms: &[TokenStream]) -> TokenStream {
    match (form, q.shape) {
        (Form::Lanes, Shape::Vector(_)) => quote!([#(#atoms),*]),
        (Form::Lanes, Shape::Matrix(rows, _)) => {
            let columns = atoms.chunks(rows).map(|c| quote!([#(#c),*]));
            quote!([#(#columns),*])
        }
        (Form::Lanes, _) => unreachable!("only vectors and matrices have a lane form"),
        (Form::Scalar, shape) => match shape {
            Shape::Vector(_) => quote!(SVector::from_array_storage(ArrayStorage([[#(#atoms),*]]))),
            Shape::Matrix(rows, _) => {
                let columns = atoms.chunks(rows).map(|c| quote!([#(#c),*]));
                quote!(SMatrix::from_array_storage(ArrayStorage([#(#columns),*])))
            }
            Shape::Pose => pose_value(atoms),
            Shape::Kinematics(_) => {
                let (pose, jacobians) = atoms.split_at(12);
                let (j, jd) = jacobians.split_at(jacobians.len() / 2);
                let pose = pose_value(pose);
                let matrix = |m: &[TokenStream]| {
                    let c: Vec<TokenStream> = m.chunks(6).map(|c| quote!([#(#c),*])).collect();
                    quote!(SMatrix::from_array_storage(ArrayStorage([#(#c),*])))
                };
                let (j, jd) = (matrix(j), matrix(jd));
                quote!((#pose, #j, #jd))
            }
            Shape::VectorPair(n, _) => {
                let (first, second) = atoms.split_at(n);
                quote!((
                    SVector::from_array_storage(ArrayStorage([[#(#first),*]])),
                    SVector::from_array_storage(ArrayStorage([[#(#second),*]])),
                ))
            }
            Shape::MatrixPair(rows, cols) => {
                let (first, second) = atoms.split_at(rows * cols);
                let (first, second) = (matrix_value(first, rows), matrix_value(second, rows));
                quote!((#first, #second))
            }
            Shape::ContactMatrices(n, c) => contact_matrices_value(atoms, n, c),
            Shape::ContactSystem(n, c) => {
                let (matrices, vectors) = atoms.split_at(2 * n * c + c * c);
                let (drift, free) = vectors.split_at(c);
                let matrices = contact_matrices_value(matrices, n, c);
                quote!(ContactSystem {
                    matrices: #matrices,
                    drift: SVector::from_array_storage(ArrayStorage([[#(#drift),*]])),
                    free_acceleration: SVector::from_array_storage(ArrayStorage([[#(#free),*]])),
                })
            }
            Shape::ContactStep(..) | Shape::ContactInertia(..) => {
                let fields = struct_fields(q.shape).expect("a struct result");
                let mut rest = atoms;
                let values = fields.iter().map(|(path, rows, cols)| {
                    let (part, after) = rest.split_at(rows * cols);
                    rest = after;
                    let value = matrix_value(part, *rows);
                    let field = path.clone().into_iter().last().expect("a field name");
                    quote!(#field: #value)
                });
                let ty = match q.shape {
                    Shape::ContactStep(..) => quote!(ContactStep),
                    _ => quote!(ContactInertia),
                };
                quote!(#ty { #(#values),* })
            }
        },
    }
}

/// Bytes of `q`'s result: `f64`s, or lane vectors of at least four.
fn result_bytes(q: &Quantity, form: Form) -> usize {
    q.outputs.len() * if form == Form::Lanes { 32 } else { 8 }
}

/// Whether a function's result is written in place, each output stored as soon as it is
/// computed: vectors and matrices (pairs of them, and structs of them), not poses and
/// kinematics.
pub(super) fn writes_in_place(q: &Quantity, form: Form) -> bool {
    matches!(
        (form, q.shape),
        (_, Shape::Vector(_) | Shape::Matrix(..))
            | (Form::Scalar, Shape::VectorPair(..) | Shape::MatrixPair(..))
    ) || (form == Form::Scalar && struct_fields(q.shape).is_some())
}

/// The matrices and vectors a struct result is made of, in the order of its outputs: each
/// field's path from the result (`.matrices.jacobian`) and its rows and columns.
fn struct_fields(shape: Shape) -> Option<Vec<(TokenStream, usize, usize)>> {
    let matrices = |path: TokenStream, n: usize, c: usize| {
        vec![
            (quote!(#path.jacobian), c, n),
            (quote!(#path.response), n, c),
            (quote!(#path.delassus), c, c),
        ]
    };
    match shape {
        Shape::ContactMatrices(n, c) => Some(matrices(quote!(), n, c)),
        Shape::ContactSystem(n, c) => {
            let mut fields = matrices(quote!(.matrices), n, c);
            fields.extend([(quote!(.drift), c, 1), (quote!(.free_acceleration), n, 1)]);
            Some(fields)
        }
        Shape::ContactStep(n, c) => Some(vec![
            (quote!(.acceleration), n, 1),
            (quote!(.forces), c, 1),
            (quote!(.previous_forces), c, 1),
            (quote!(.delassus), c, c),
            (quote!(.pivots), c, 1),
            (quote!(.rhs), c, 1),
        ]),
        Shape::ContactInertia(c) => Some(vec![
            (quote!(.inertia), c, c),
            (quote!(.pivots), c, 1),
            (quote!(.delassus_diagonal), c, 1),
        ]),
        _ => None,
    }
}

/// Where outputs go in a result written in place: per output its slot (`o17`, bound as a
/// `&mut` to the entry) or `_` (a zero, left as filled); which computed value each slot
/// receives; and the writes of outputs that are inputs or constants (`*o0 = a0;`). Only the
/// outputs `here` accepts get slots (a chunk writes the ones it computes).
pub(super) struct OutputSlots {
    pub(super) pattern: Vec<TokenStream>,
    pub(super) slots: HashMap<Id, Vec<Ident>>,
    pub(super) immediate: Vec<TokenStream>,
}

impl OutputSlots {
    pub(super) fn new(
        plan: &Plan,
        q: &Quantity,
        atoms: &[TokenStream],
        here: impl Fn(Id) -> bool,
    ) -> OutputSlots {
        let g = &plan.robot.graph;
        let mut slots: HashMap<Id, Vec<Ident>> = HashMap::new();
        let mut immediate = Vec::new();
        let pattern = q
            .outputs
            .iter()
            .zip(atoms)
            .enumerate()
            .map(|(k, (&id, atom))| {
                let slot = format_ident!("o{k}");
                if is_structural_zero(g, id) || !here(id) {
                    return quote!(_);
                }
                match plan.names.contains_key(&id) {
                    true => slots.entry(id).or_default().push(slot.clone()),
                    false => immediate.push(match plan.form {
                        Form::Scalar => quote!(*#slot = #atom;),
                        Form::Lanes => quote!(*#slot = dyngen_runtime::__private::lane_out(arith, #atom);),
                    }),
                }
                quote!(#slot)
            })
            .collect();
        OutputSlots {
            pattern,
            slots,
            immediate,
        }
    }

    /// Whether any output has a slot.
    pub(super) fn any(&self) -> bool {
        !self.slots.is_empty() || !self.immediate.is_empty()
    }
}

/// The pattern binding the result's entries, nested as the result's storage is.
pub(super) fn slots_pattern(q: &Quantity, form: Form, pattern: &[TokenStream]) -> TokenStream {
    let nested = |entries: &[TokenStream], rows: usize| {
        // An entry stored with its column's vector ([`OutputSlots::store_four_lanes_whole`]) is
        // bound by the rest pattern before it, and left empty here.
        let columns = (entries.chunks(rows))
            .map(|c| c.iter().filter(|e| !e.is_empty()))
            .map(|c| quote!([#(#c),*]));
        quote!([#(#columns),*])
    };
    match (form, q.shape) {
        (Form::Scalar, Shape::Vector(rows) | Shape::Matrix(rows, _))
        | (Form::Lanes, Shape::Matrix(rows, _)) => nested(pattern, rows),
        (Form::Lanes, Shape::Vector(_)) => quote!([#(#pattern),*]),
        (Form::Scalar, Shape::VectorPair(n, _)) => {
            let (first, second) = pattern.split_at(n);
            quote!(([#(#first),*], [#(#second),*]))
        }
        (Form::Scalar, Shape::MatrixPair(rows, cols)) => {
            let (first, second) = pattern.split_at(rows * cols);
            let (first, second) = (nested(first, rows), nested(second, rows));
            quote!((#first, #second))
        }
        (Form::Scalar, shape) => {
            let fields = struct_fields(shape)
                .expect("only vectors, matrices, their pairs and structs are written in place");
            let mut rest = pattern;
            let parts = fields.iter().map(|&(_, rows, cols)| {
                let (part, after) = rest.split_at(rows * cols);
                rest = after;
                nested(part, rows)
            });
            let parts: Vec<TokenStream> = parts.collect();
            quote!((#(#parts),*))
        }
        _ => unreachable!("only vectors, matrices and their pairs are written in place"),
    }
}

/// The mutable place [`slots_pattern`] binds, of the result `out` (a local, or a `&mut` to the
/// result when `by_reference`).
pub(super) fn slots_target(q: &Quantity, form: Form, out: TokenStream, by_reference: bool) -> TokenStream {
    match (form, q.shape) {
        (Form::Scalar, Shape::Vector(_) | Shape::Matrix(..)) => quote!(&mut #out.data.0),
        (Form::Scalar, Shape::VectorPair(..)) => quote!((&mut #out.0.data.0[0], &mut #out.1.data.0[0])),
        (Form::Scalar, Shape::MatrixPair(..)) => quote!((&mut #out.0.data.0, &mut #out.1.data.0)),
        (Form::Lanes, Shape::Vector(_) | Shape::Matrix(..)) => match by_reference {
            true => out,
            false => quote!(&mut #out),
        },
        (Form::Scalar, shape) => {
            let fields = struct_fields(shape)
                .expect("only vectors, matrices, their pairs and structs are written in place");
            let targets = fields.iter().map(|(path, _, _)| quote!(&mut #out #path.data.0));
            quote!((#(#targets),*))
        }
        _ => unreachable!("only vectors, matrices and their pairs are written in place"),
    }
}

/// The zero a result written in place starts from; a lane result's in the caller's lane type
/// (`C`, in the lane kernel). One of more than [`Sizes::library_fill_bytes`], up to
/// [`Sizes::unrolled_fill_bytes`], is filled by `dyngen_runtime::__private::fill_zero()`.
pub(super) fn zero_result(q: &Quantity, form: Form, sizes: &Sizes) -> TokenStream {
    let bytes = result_bytes(q, form);
    let library_fill = bytes > sizes.library_fill_bytes && bytes <= sizes.unrolled_fill_bytes;
    let (matrix, fill) = match library_fill {
        true => (
            quote!(SMatrix::from_element(dyngen_runtime::__private::fill_zero())),
            quote!(dyngen_runtime::__private::fill_zero()),
        ),
        false => (quote!(SMatrix::zeros()), quote!(0.0)),
    };
    match (form, q.shape) {
        (Form::Scalar, Shape::Vector(_) | Shape::Matrix(..)) => matrix,
        (Form::Scalar, Shape::VectorPair(..) | Shape::MatrixPair(..)) => quote!((#matrix, #matrix)),
        (Form::Scalar, Shape::ContactMatrices(..)) => quote!(ContactMatrices {
            jacobian: #matrix,
            response: #matrix,
            delassus: #matrix,
        }),
        (Form::Scalar, Shape::ContactSystem(..)) => quote!(ContactSystem {
            matrices: ContactMatrices {
                jacobian: #matrix,
                response: #matrix,
                delassus: #matrix,
            },
            drift: #matrix,
            free_acceleration: #matrix,
        }),
        (Form::Scalar, Shape::ContactStep(..)) => quote!(ContactStep {
            acceleration: #matrix,
            forces: #matrix,
            previous_forces: #matrix,
            delassus: #matrix,
            pivots: #matrix,
            rhs: #matrix,
        }),
        (Form::Scalar, Shape::ContactInertia(..)) => quote!(ContactInertia {
            inertia: #matrix,
            pivots: #matrix,
            delassus_diagonal: #matrix,
        }),
        (Form::Lanes, shape) => {
            let splat = quote!(C::splat(#fill));
            match shape {
                Shape::Vector(len) => {
                    let len = Literal::usize_unsuffixed(len);
                    quote!([#splat; #len])
                }
                Shape::Matrix(rows, cols) => {
                    let (r, c) = (Literal::usize_unsuffixed(rows), Literal::usize_unsuffixed(cols));
                    quote!([[#splat; #r]; #c])
                }
                _ => unreachable!("only vectors and matrices have a lane form"),
            }
        }
        _ => unreachable!("only vectors, matrices and their pairs are written in place"),
    }
}

/// An `SMatrix` of `rows` rows from its entries, column-major.
fn matrix_value(atoms: &[TokenStream], rows: usize) -> TokenStream {
    let columns = atoms.chunks(rows).map(|c| quote!([#(#c),*]));
    quote!(SMatrix::from_array_storage(ArrayStorage([#(#columns),*])))
}

/// `ContactMatrices` of `n` velocity coordinates and `c` rows from `J`, `M⁻¹ Jᵀ` and `K`,
/// each column-major.
fn contact_matrices_value(atoms: &[TokenStream], n: usize, c: usize) -> TokenStream {
    let (jacobian, rest) = atoms.split_at(c * n);
    let (response, delassus) = rest.split_at(n * c);
    let (jacobian, response, delassus) = (
        matrix_value(jacobian, c),
        matrix_value(response, n),
        matrix_value(delassus, c),
    );
    quote!(ContactMatrices {
        jacobian: #jacobian,
        response: #response,
        delassus: #delassus,
    })
}

/// A `Pose` from 12 atoms: the rotation column-major, then the translation.
fn pose_value(atoms: &[TokenStream]) -> TokenStream {
    let (r, p) = atoms.split_at(9);
    let columns = r.chunks(3).map(|c| quote!([#(#c),*]));
    quote!(Pose {
        rotation: Matrix3::from_array_storage(ArrayStorage([#(#columns),*])),
        translation: Vector3::new(#(#p),*),
    })
}
