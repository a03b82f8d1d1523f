//! How much of a frame's motion a contact holds.

/// How much of a frame's motion a contact holds: its origin (a point) or all of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ContactKind {
    /// The frame's origin (three rows): a foot on the ground, a fingertip.
    Point,
    /// The whole frame (six rows, linear first): a flat foot, a hand gripping a handle.
    Frame,
}

impl ContactKind {
    /// The rows a contact of this kind adds.
    pub const fn rows(self) -> usize {
        match self {
            ContactKind::Point => 3,
            ContactKind::Frame => 6,
        }
    }

    /// The name a description writes: `point` or `frame`.
    pub const fn keyword(self) -> &'static str {
        match self {
            ContactKind::Point => "point",
            ContactKind::Frame => "frame",
        }
    }
}
