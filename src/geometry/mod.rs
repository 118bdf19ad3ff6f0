//! Geometry built from a scene for the passes that do not draw the base mesh: the displaced
//! mesh (Tessellated, the references) and the prisms (Prism). Depends on `mesh` and `scene`;
//! nothing there depends on it.

pub mod prisms;
pub mod tessellate;
