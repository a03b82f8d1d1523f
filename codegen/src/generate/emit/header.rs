//! What a generated function is, whole or in chunks: its name, result type and doc, and which
//! dispatch its kernels take ([`Header`]); and what emitting it gives ([`Emitted`]).

use super::lane_width::LaneWidth;
use super::outputs::result_type;
use super::plan::{Form, Plan};
use super::sizes::Sizes;
use crate::generate::quantities::Shape;
use crate::generate::trace::Quantity;
use crate::symbolic::OpCounts;
use proc_macro2::{Ident, Literal, TokenStream};
use quote::format_ident;

/// A generated function: its trait method, and the chunk functions it calls (if it is large).
pub(super) struct Emitted {
    pub(super) method: TokenStream,
    pub(super) chunks: Vec<TokenStream>,
}

/// Suffix of the lane form of a function's name: `inverse_dynamics_lanes`.
const LANES_SUFFIX: &str = "_lanes";

/// What a generated function is called, returns and says.
pub(super) struct Header {
    /// The method's name: the quantity's, with [`Header::suffix`].
    pub(super) name: Ident,
    /// `_lanes` for the lane form (whose chunks are `<name>_lanes_partK`), else empty.
    pub(super) suffix: &'static str,
    /// The result type, a lane function's in its lane type `L`.
    pub(super) ret: TokenStream,
    /// The length of a velocity-space argument.
    pub(super) n: Literal,
    /// Whether its kernels hold far more values than registers (the derivatives of the
    /// dynamics, and functions of more than [`Sizes::many_values`] values): run through
    /// `dispatch_many`.
    pub(super) many_registers: bool,
    /// Its operations, for its doc.
    counts: OpCounts,
    /// The width of its lane vectors, for its doc.
    lanes: LaneWidth,
    /// A base regressor's doc names the columns of `Y` it is.
    columns: Option<String>,
}

impl Header {
    /// The header of `q` planned as `plan`, its velocity-space arguments of `n` entries.
    pub(super) fn new(plan: &Plan, q: &Quantity, n: usize, sizes: &Sizes) -> Header {
        let suffix = match plan.form {
            Form::Scalar => "",
            Form::Lanes => LANES_SUFFIX,
        };
        let robot = plan.robot;
        let columns = q.kind.uses_base_columns().then(|| {
            let columns: Vec<String> = robot.base.columns.iter().map(|c| c.to_string()).collect();
            format!(
                " `Y_b`: columns {} of `Y` (the base parameters'), computed without the others.",
                columns.join(", ")
            )
        });
        Header {
            name: format_ident!("{}{suffix}", q.name()),
            suffix,
            ret: result_type(q, plan.form),
            n: Literal::usize_unsuffixed(n),
            many_registers: matches!(q.shape, Shape::MatrixPair(..)) || plan.order.len() > sizes.many_values,
            counts: robot.graph.op_counts(&q.outputs),
            lanes: plan.lanes,
            columns,
        }
    }

    /// The doc lines: the base columns of a base regressor, then the operations, less the
    /// `stored_whole` lane extractions the function leaves out because it stores their vector
    /// whole.
    pub(super) fn doc(&self, stored_whole: usize) -> Vec<String> {
        let mut counts = self.counts;
        counts.lanes -= stored_whole;
        let operations = doc_counts(&counts, self.lanes);
        self.columns.iter().cloned().chain([operations]).collect()
    }
}

fn doc_counts(c: &OpCounts, lanes: LaneWidth) -> String {
    let mut s = format!("Operations: {} mul, {} add/sub, {} neg", c.mul, c.add, c.neg);
    if c.div > 0 {
        s += &format!(", {} div", c.div);
    }
    if c.trig > 0 {
        s += &format!(", {} sin/cos", c.trig);
    }
    if c.friction > 0 {
        s += &format!(", {} sign/tanh", c.friction);
    }
    if c.lanes > 0 {
        let (ty, count) = match lanes {
            LaneWidth::Four => ("f64x4", "four"),
            LaneWidth::Eight => ("f64x8", "eight"),
        };
        s += &format!(
            ", and {} lane ops ({ty}: each on {count} lanes at once; splats, seeds and lane \
             extractions included)",
            c.lanes
        );
    }
    s + " (joint sines and cosines come precomputed in `JointTrig`)."
}
