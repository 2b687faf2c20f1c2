//! Geometry: meshes split at atlas seams, one node per instance (TRS, or
//! the transform applied to the vertices), analytic area lights as meshes.

use super::*;

/// One scene mesh with its vertices split at atlas seams: shared by every
/// instance of the mesh whose transform is a TRS.
pub(super) struct SplitMesh {
    /// Per output vertex: the mesh vertex and the layout coordinate (unit
    /// square of the mesh; `None` without a layout).
    pub(super) vertices: Vec<(u32, Option<Vec2>)>,
    /// Per triangle (mesh order): output vertex indices.
    pub(super) triangles: Vec<[u32; 3]>,
}

impl MeshAccessors {
    /// The primitive attributes of the shared data (TEXCOORD_1 is added per
    /// instance).
    pub(super) fn attributes(&self) -> Map<String, Value> {
        let mut attributes = Map::new();
        attributes.insert("POSITION".into(), json!(self.position));
        if let Some(n) = self.normal {
            attributes.insert("NORMAL".into(), json!(n));
        }
        if let Some(t) = self.uv0 {
            attributes.insert("TEXCOORD_0".into(), json!(t));
        }
        attributes
    }
}

impl SplitMesh {
    pub(super) fn new(mesh: &Mesh, layout: Option<&crate::atlas::MeshLayout>) -> Self {
        let mut vertices = Vec::new();
        let mut index: HashMap<(u32, u64), u32> = HashMap::new();
        let mut triangles = Vec::with_capacity(mesh.indices.len());
        for (t, tri) in mesh.indices.iter().enumerate() {
            let mut out = [0u32; 3];
            for c in 0..3 {
                let uv = layout.map(|l| l.corner_uvs[t][c]);
                let bits = uv.map_or(0, |u| ((u.x.to_bits() as u64) << 32) | u.y.to_bits() as u64);
                out[c] = *index.entry((tri[c], bits)).or_insert_with(|| {
                    vertices.push((tri[c], uv));
                    (vertices.len() - 1) as u32
                });
            }
            triangles.push(out);
        }
        Self {
            vertices,
            triangles,
        }
    }
}

/// Accessors of one mesh's shared data.
#[derive(Clone, Copy)]
pub(super) struct MeshAccessors {
    pub(super) position: usize,
    pub(super) normal: Option<usize>,
    pub(super) uv0: Option<usize>,
    pub(super) indices: usize,
}

/// Object-to-world transform as glTF TRS, if it is one (no shear, last row
/// 0 0 0 1): (translation, unit rotation, scale).
pub(super) fn as_trs(m: Mat4) -> Option<(Vec3, Quat, Vec3)> {
    if m.row(3) != glam::Vec4::W {
        return None;
    }
    let (s, r, t) = m.to_scale_rotation_translation();
    let r = r.normalize();
    if !(s.is_finite() && r.is_finite() && t.is_finite()) {
        return None;
    }
    let back = Mat4::from_scale_rotation_translation(s, r, t);
    let a = m.to_cols_array();
    let b = back.to_cols_array();
    let size = a.iter().fold(0.0f32, |acc, x| acc.max(x.abs()));
    let err = a
        .iter()
        .zip(&b)
        .fold(0.0f32, |acc, (x, y)| acc.max((x - y).abs()));
    (err <= 1e-5 * size.max(f32::MIN_POSITIVE)).then_some((t, r, s))
}

pub(super) fn trs_json(node: &mut Map<String, Value>, t: Vec3, r: Quat, s: Vec3) {
    if t != Vec3::ZERO {
        node.insert("translation".into(), nums(&t.to_array()));
    }
    if r != Quat::IDENTITY {
        node.insert("rotation".into(), nums(&r.to_array()));
    }
    if s != Vec3::ONE {
        node.insert("scale".into(), nums(&s.to_array()));
    }
}

/// TEXCOORD_1 of one instance: the page coordinates of each split vertex
/// (computed as [`crate::Atlas::triangle_uvs`] computes them).
pub(super) fn uv1_data(split: &SplitMesh, rect: crate::atlas::InstanceRect) -> Vec<f32> {
    split
        .vertices
        .iter()
        .flat_map(|&(_, uv)| rect.map(uv.unwrap_or(Vec2::ZERO)).to_array())
        .collect()
}

impl Builder<'_> {
    /// Per-vertex data of `split` from `mesh`, transformed by `m` (normals
    /// by its inverse transpose, renormalised), and the triangles with their
    /// winding reversed when `flip`.
    pub(super) fn vertex_data(
        &mut self,
        mesh: &Mesh,
        split: &SplitMesh,
        m: Mat4,
        flip: bool,
    ) -> MeshAccessors {
        let normal_m = Mat3::from_mat4(m).inverse().transpose();
        let positions: Vec<f32> = split
            .vertices
            .iter()
            .flat_map(|&(v, _)| m.transform_point3(mesh.positions[v as usize]).to_array())
            .collect();
        let position = self.float_accessor(&positions, "VEC3", 3, true);
        let normal = mesh.normals.as_ref().map(|normals| {
            // A face normal of a triangle using the vertex, for zero normals.
            let mut face = vec![Vec3::Z; split.vertices.len()];
            for (t, tri) in mesh.indices.iter().enumerate() {
                let p = |c: usize| mesh.positions[tri[c] as usize];
                let n = (p(1) - p(0)).cross(p(2) - p(0)).normalize_or_zero();
                for c in 0..3 {
                    face[split.triangles[t][c] as usize] = n;
                }
            }
            let data: Vec<f32> = split
                .vertices
                .iter()
                .enumerate()
                .flat_map(|(k, &(v, _))| {
                    let n = normals[v as usize];
                    let n = if n.length_squared() > 0.0 { n } else { face[k] };
                    let w = (normal_m * n).normalize_or_zero();
                    let w = if w == Vec3::ZERO { Vec3::Z } else { w };
                    w.to_array()
                })
                .collect();
            self.float_accessor(&data, "VEC3", 3, false)
        });
        let uv0 = mesh.uv0.as_ref().map(|uv| {
            let data: Vec<f32> = split
                .vertices
                .iter()
                .flat_map(|&(v, _)| uv[v as usize].to_array())
                .collect();
            self.float_accessor(&data, "VEC2", 2, false)
        });
        let triangles: Vec<[u32; 3]> = if flip {
            split.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect()
        } else {
            split.triangles.clone()
        };
        let indices = self.index_accessor(&triangles, split.vertices.len());
        MeshAccessors {
            position,
            normal,
            uv0,
            indices,
        }
    }

    pub(super) fn instance(&mut self, i: usize) -> Result<(), BakeError> {
        let scene = self.scene;
        let inst = &scene.instances[i];
        let mesh = &scene.meshes[inst.mesh];
        if mesh.indices.is_empty() {
            return Ok(());
        }
        let layout = self.bake.atlas.meshes[inst.mesh].as_ref();
        let rect = self.bake.atlas.instances[i];
        let trs = as_trs(inst.transform);
        let (acc, uv1) = match trs {
            Some(_) => {
                if !self.split.contains_key(&inst.mesh) {
                    let split = SplitMesh::new(mesh, layout);
                    let acc = self.vertex_data(mesh, &split, Mat4::IDENTITY, false);
                    self.split.insert(inst.mesh, (split, acc));
                }
                let (split, acc) = &self.split[&inst.mesh];
                let uv1 = rect.map(|r| uv1_data(split, r));
                (*acc, uv1)
            }
            None => {
                // Not a TRS: the transform goes into the vertices.
                let split = SplitMesh::new(mesh, layout);
                let acc = self.vertex_data(mesh, &split, inst.transform, inst.flips_winding());
                (acc, rect.map(|r| uv1_data(&split, r)))
            }
        };
        let uv1 = uv1.map(|d| self.float_accessor(&d, "VEC2", 2, false));
        if uv1.is_none() {
            self.warnings.push(format!(
                "instance {i} ('{}') has no texels in the atlas: exported without ambient occlusion",
                mesh.name
            ));
        }
        let material_id = inst.material.unwrap_or(mesh.material);
        let page = rect.map(|r| r.page);
        let material = self.material(material_id, page, acc.uv0.is_some())?;
        let mut attributes = acc.attributes();
        if let Some(t) = uv1 {
            attributes.insert("TEXCOORD_1".into(), json!(t));
        }
        self.meshes.push(json!({
            "name": mesh.name,
            "primitives": [{
                "attributes": attributes,
                "indices": acc.indices,
                "material": material,
            }],
        }));
        let mut node = Map::new();
        node.insert("name".into(), json!(mesh.name));
        node.insert("mesh".into(), json!(self.meshes.len() - 1));
        if let Some((t, r, s)) = trs {
            trs_json(&mut node, t, r, s);
        }
        self.nodes.push(Value::Object(node));
        Ok(())
    }

    /// An analytic area light as an emissive mesh.
    pub(super) fn area_light(&mut self, l: usize) -> Result<(), BakeError> {
        let scene = self.scene;
        let al = &scene.area_lights[l];
        let (mut mesh, what) = match al.light.shape {
            Shape::Sphere { center, radius } => (
                penumbra_scene::primitives::sphere(center, radius, 16),
                "sphere",
            ),
            Shape::Disk {
                center,
                normal,
                radius,
            } => (
                penumbra_scene::primitives::disk(center, normal, radius, 64),
                "disk",
            ),
            Shape::Quad {
                corner,
                edge1,
                edge2,
            } => (
                penumbra_scene::primitives::quad(corner, edge1, edge2),
                "quad",
            ),
        };
        mesh.remove_degenerate();
        if mesh.indices.is_empty() {
            return Ok(());
        }
        self.warnings.push(format!(
            "area light '{}' ({what}) exported as an emissive mesh (glTF has no area lights)",
            al.name
        ));
        let split = SplitMesh::new(&mesh, None);
        let acc = self.vertex_data(&mesh, &split, Mat4::IDENTITY, false);
        let emitter = Material {
            double_sided: al.light.two_sided,
            ..Material::emitter(al.name.clone(), al.light.radiance)
        };
        let (mut m, _) = self.convert(&emitter, None, false)?;
        m.insert("name".into(), json!(al.name));
        self.materials.push(Value::Object(m));
        let material = self.materials.len() - 1;
        let attributes = acc.attributes();
        self.meshes.push(json!({
            "name": al.name,
            "primitives": [{
                "attributes": attributes,
                "indices": acc.indices,
                "material": material,
            }],
        }));
        self.nodes.push(json!({
            "name": al.name,
            "mesh": self.meshes.len() - 1,
        }));
        Ok(())
    }
}
