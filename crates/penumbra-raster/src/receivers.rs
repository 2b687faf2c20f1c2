//! Planar shadow receivers: the instances whose every vertex lies on one
//! world plane, either those the scene marks (`Instance::planar_receiver`)
//! or, without marks, the one of largest area; and for each receiver the
//! instances that can cast onto it (all but those lying in its plane).

use glam::{Vec3, Vec4};
use penumbra_scene::Scene;
use penumbra_scene::mesh::Instance;

/// Most receivers per frame (stencil values 1..=127; the top bit marks
/// shadow).
pub const MAX_RECEIVERS: usize = 127;

/// Vertices within this fraction of the instance's (or, for coplanarity
/// with a receiver, the scene's) bounding diagonal count as on the plane.
const PLANE_TOLERANCE: f32 = 1e-4;

/// One planar receiver.
#[derive(Clone, Debug, PartialEq)]
pub struct Receiver {
    pub instance: usize,
    /// World plane (n, d), n·x + d = 0, |n| = 1.
    pub plane: Vec4,
    /// Instances that may cast onto it (every instance not in its plane).
    pub occluders: Vec<usize>,
}

fn world_vertices(scene: &Scene, inst: &Instance) -> Vec<Vec3> {
    scene.meshes[inst.mesh]
        .positions
        .iter()
        .map(|p| inst.transform.transform_point3(*p))
        .collect()
}

/// Whether every point lies within `tol` of `plane`.
fn on_plane(points: &[Vec3], plane: Vec4, tol: f32) -> bool {
    points.iter().all(|p| plane.dot(p.extend(1.0)).abs() <= tol)
}

/// The world plane of an instance whose vertices all lie on one plane
/// (within [`PLANE_TOLERANCE`] of its diagonal), from its largest
/// triangle's normal; `None` if it is not planar or has no area.
pub fn instance_plane(scene: &Scene, inst: &Instance) -> Option<Vec4> {
    let world = world_vertices(scene, inst);
    let mut best = (0.0f32, Vec3::ZERO, Vec3::ZERO);
    for t in &scene.meshes[inst.mesh].indices {
        let [a, b, c] = t.map(|i| world[i as usize]);
        let n = (b - a).cross(c - a);
        let area2 = n.length_squared();
        if area2 > best.0 {
            best = (area2, n, a);
        }
    }
    if best.0 <= 0.0 || !best.0.is_finite() {
        return None;
    }
    let n = best.1.normalize();
    let plane = n.extend(-n.dot(best.2));
    let (lo, hi) = world.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    on_plane(&world, plane, PLANE_TOLERANCE * (hi - lo).length()).then_some(plane)
}

/// The frame's receivers and warnings about marks that could not be used;
/// `bounds` are the scene's (coplanarity is judged relative to them).
pub fn planar_receivers(scene: &Scene, bounds: (Vec3, Vec3)) -> (Vec<Receiver>, Vec<String>) {
    let mut warnings = Vec::new();
    let marked: Vec<usize> = (0..scene.instances.len())
        .filter(|&i| scene.instances[i].planar_receiver)
        .collect();
    let mut chosen: Vec<(usize, Vec4)> = Vec::new();
    if marked.is_empty() {
        let mut best: Option<(f32, usize, Vec4)> = None;
        for (i, inst) in scene.instances.iter().enumerate() {
            if let Some(plane) = instance_plane(scene, inst) {
                let area = scene.instance_area(inst);
                if best.is_none_or(|b| area > b.0) {
                    best = Some((area, i, plane));
                }
            }
        }
        chosen.extend(best.map(|(_, i, p)| (i, p)));
        if chosen.is_empty() {
            warnings.push(
                "raster: --shadows planar: the scene has no planar object to receive shadows"
                    .to_string(),
            );
        }
    } else {
        for i in marked {
            let name = &scene.meshes[scene.instances[i].mesh].name;
            match instance_plane(scene, &scene.instances[i]) {
                Some(p) if chosen.len() < MAX_RECEIVERS => chosen.push((i, p)),
                Some(_) => warnings.push(format!(
                    "raster: more than {MAX_RECEIVERS} planar receivers; '{name}' (instance {i}) receives no planar shadows"
                )),
                None => warnings.push(format!(
                    "raster: '{name}' (instance {i}) is marked planar_receiver but is not planar; it receives no planar shadows"
                )),
            }
        }
    }
    let tol = PLANE_TOLERANCE * (bounds.1 - bounds.0).length();
    let receivers = chosen
        .into_iter()
        .map(|(instance, plane)| {
            let occluders = (0..scene.instances.len())
                .filter(|&j| {
                    j != instance
                        && !on_plane(&world_vertices(scene, &scene.instances[j]), plane, tol)
                })
                .collect();
            Receiver {
                instance,
                plane,
                occluders,
            }
        })
        .collect();
    (receivers, warnings)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;
    use penumbra_scene::primitives;

    fn scene() -> Scene {
        let mut s = Scene::default();
        // Floor 10 × 10 at y = 0, a small quad tilted at y = 2, a box on the
        // floor, a 2 × 2 tile lying on the floor.
        s.add_mesh(
            primitives::quad(
                Vec3::new(-5.0, 0.0, 5.0),
                Vec3::new(10.0, 0.0, 0.0),
                Vec3::new(0.0, 0.0, -10.0),
            ),
            Mat4::IDENTITY,
        );
        s.add_mesh(
            primitives::quad(Vec3::ZERO, Vec3::X, Vec3::new(0.0, 1.0, -1.0)),
            Mat4::from_translation(Vec3::new(0.0, 2.0, 0.0)),
        );
        s.add_mesh(primitives::cuboid(Vec3::ZERO, Vec3::ONE), Mat4::IDENTITY);
        s.add_mesh(
            primitives::quad(
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 0.0, -2.0),
            ),
            Mat4::IDENTITY,
        );
        s
    }

    #[test]
    fn the_largest_planar_instance_receives_and_coplanar_ones_do_not_cast() {
        let s = scene();
        assert!(
            instance_plane(&s, &s.instances[2]).is_none(),
            "a box is not planar"
        );
        let tilted = instance_plane(&s, &s.instances[1]).unwrap();
        assert!((tilted.truncate().dot(Vec3::new(0.0, 1.0, 1.0).normalize())).abs() > 0.999);
        let (r, w) = planar_receivers(&s, s.bounds().unwrap());
        assert!(w.is_empty(), "{w:?}");
        assert_eq!(r.len(), 1);
        assert_eq!(r[0].instance, 0);
        let n = r[0].plane.truncate();
        assert!((n.y.abs() - 1.0).abs() < 1e-6 && r[0].plane.w.abs() < 1e-6);
        // The tile on the floor is in its plane; the tilted quad and the box cast.
        assert_eq!(r[0].occluders, [1, 2]);
    }

    #[test]
    fn marked_instances_receive_and_bad_marks_warn() {
        let mut s = scene();
        s.instances[1].planar_receiver = true;
        s.instances[2].planar_receiver = true;
        let (r, w) = planar_receivers(&s, s.bounds().unwrap());
        assert_eq!(r.iter().map(|r| r.instance).collect::<Vec<_>>(), [1]);
        assert_eq!(r[0].occluders, [0, 2, 3]);
        assert_eq!(w.len(), 1);
        assert!(w[0].contains("not planar"), "{w:?}");
    }
}
