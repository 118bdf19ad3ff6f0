//! What one walk of a light's disk as a bundle (bundle.rs) shows of its rays.

use super::prism::Place;

/// What a bundle shows of its rays.
pub(super) enum Bundle {
    /// every one meets the surface
    Blocked,
    /// every one leaves the object's shell unblocked through a top; true where the object
    /// must still be searched there (anything of it lies above the triangles the bundle left
    /// by or began in, or their neighbours)
    Left(bool),
    /// no ray meets the surface before the axis's place
    Cleared(Place),
}
