//! Analytic shapes tessellated to triangle meshes (to be written).
