//! `EXT_mesh_gpu_instancing`: a node's mesh drawn once per row of its
//! TRANSLATION, ROTATION and SCALE accessors (any of them may be absent;
//! present ones have equal counts), row k as `world · T_k · R_k · S_k`.
//! Rotations are unit quaternions (x, y, z, w), float or normalised
//! integers, renormalised.

use super::Loader;
use crate::error::SceneError;
use ::gltf::json::accessor::Type;
use glam::{Mat4, Quat, Vec3};

impl Loader<'_> {
    /// The world transforms of node `n`'s mesh: `[world]`, or one per row
    /// of its instancing attributes.
    pub(super) fn mesh_instances(&self, n: usize, world: Mat4) -> Result<Vec<Mat4>, SceneError> {
        let ext = &self.value["nodes"][n]["extensions"]["EXT_mesh_gpu_instancing"];
        if !ext.is_object() {
            return Ok(vec![world]);
        }
        let path = format!("nodes[{n}].extensions.EXT_mesh_gpu_instancing.attributes");
        let accessor = |name: &str| -> Result<Option<usize>, SceneError> {
            match ext["attributes"].get(name) {
                None => Ok(None),
                Some(v) => v
                    .as_u64()
                    .map(|i| Some(i as usize))
                    .ok_or_else(|| self.err(format!("{path}.{name}"), "must be an accessor index")),
            }
        };
        let translation = match accessor("TRANSLATION")? {
            Some(i) => Some(self.read_vec3(i, &format!("{path}.TRANSLATION"))?),
            None => None,
        };
        let rotation = match accessor("ROTATION")? {
            Some(i) => {
                let f = self.read_floats(i, &format!("{path}.ROTATION"), Type::Vec4)?;
                let q: Vec<Quat> = f
                    .chunks_exact(4)
                    .map(|c| Quat::from_xyzw(c[0], c[1], c[2], c[3]))
                    .collect();
                if let Some(k) = q.iter().position(|q| !q.is_finite() || q.length() < 1e-6) {
                    return Err(self.err(
                        format!("{path}.ROTATION"),
                        format!("row {k} is not a rotation (zero or non-finite quaternion)"),
                    ));
                }
                Some(q.into_iter().map(Quat::normalize).collect::<Vec<_>>())
            }
            None => None,
        };
        let scale = match accessor("SCALE")? {
            Some(i) => Some(self.read_vec3(i, &format!("{path}.SCALE"))?),
            None => None,
        };
        let counts = [
            ("TRANSLATION", translation.as_ref().map(Vec::len)),
            ("ROTATION", rotation.as_ref().map(Vec::len)),
            ("SCALE", scale.as_ref().map(Vec::len)),
        ];
        let present: Vec<(&str, usize)> = counts
            .iter()
            .filter_map(|(name, c)| c.map(|c| (*name, c)))
            .collect();
        let Some(&(_, count)) = present.first() else {
            return Err(self.err(path, "no TRANSLATION, ROTATION or SCALE attribute"));
        };
        if let Some((name, c)) = present.iter().find(|(_, c)| *c != count) {
            return Err(self.err(
                format!("{path}.{name}"),
                format!("{c} rows, but {} has {count}", present[0].0),
            ));
        }
        Ok((0..count)
            .map(|k| {
                let t = translation.as_ref().map_or(Vec3::ZERO, |v| v[k]);
                let r = rotation.as_ref().map_or(Quat::IDENTITY, |v| v[k]);
                let s = scale.as_ref().map_or(Vec3::ONE, |v| v[k]);
                world * Mat4::from_scale_rotation_translation(s, r, t)
            })
            .collect())
    }
}
