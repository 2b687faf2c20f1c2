//! The scene flattened for tracing (`SceneGeometry`): what a hit reports
//! (point, distance, normals through the normal matrix, UVs, vertex colour,
//! material), where each triangle came from, front faces under mirroring
//! transforms, tangents, UV-to-world area ratios, and analytic area lights
//! against triangles. Every expected value is worked out by hand from the
//! triangle (0,0,0), (2,0,0), (0,3,0) and the ray through (0.5, 1.5), where
//! its barycentrics are b1 = x/2 = 1/4 and b2 = y/3 = 1/2.

mod common;

use glam::{Mat4, Vec2, Vec3, Vec4};
use penumbra_scene::{Instance, Material, Mesh, Scene, SceneAreaLight};
use penumbra_shading::Rgb;
use penumbra_shading::light::Shape;
use penumbra_trace::accel::BuildQuality;
use penumbra_trace::geometry::SceneGeometry;
use penumbra_trace::ray::Ray;

const B1: f32 = 0.25;
const B2: f32 = 0.5;

/// The triangle (0,0,0), (2,0,0), (0,3,0), front +z, with every
/// attribute: normals (0,0,1), (0,0,1), (1,0,1) (interpolated: (½, 0, 1));
/// UV set 0 the barycentric corners (area ½), set 1 twice them (area 2);
/// colours red, green, blue; tangents +x, +x, +y (w from vertex 0: +1).
fn triangle(material: usize) -> Mesh {
    Mesh {
        name: "t".into(),
        positions: vec![
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 3.0, 0.0),
        ],
        normals: Some(vec![Vec3::Z, Vec3::Z, Vec3::new(1.0, 0.0, 1.0)]),
        uv0: Some(vec![Vec2::ZERO, Vec2::X, Vec2::Y]),
        uv1: Some(vec![Vec2::ZERO, Vec2::X * 2.0, Vec2::Y * 2.0]),
        colors: Some(vec![Rgb::X, Rgb::Y, Rgb::Z]),
        tangents: Some(vec![
            Vec4::new(1.0, 0.0, 0.0, 1.0),
            Vec4::new(1.0, 0.0, 0.0, 1.0),
            Vec4::new(0.0, 1.0, 0.0, -1.0),
        ]),
        indices: vec![[0, 1, 2]],
        material,
    }
}

/// Instances of the triangle: 0 as it is; 1 moved to x = 10 and stretched
/// ×2 along x, with material 1; 2 mirrored in x and moved to x = −10; and
/// 3 a bare two-triangle quad (no normals, UVs from the quad, no set 1, no
/// tangents) at x = 20.
fn scene() -> Scene {
    let mut s = Scene::default();
    s.add_material(Material::lambert("a", Rgb::splat(0.5)));
    s.add_material(Material::lambert("b", Rgb::splat(0.25)));
    let mesh = s.add_mesh(triangle(0), Mat4::IDENTITY);
    s.instances.push(Instance {
        material: Some(1),
        ..Instance::new(
            mesh,
            Mat4::from_translation(Vec3::X * 10.0) * Mat4::from_scale(Vec3::new(2.0, 1.0, 1.0)),
        )
    });
    s.instances.push(Instance::new(
        mesh,
        Mat4::from_translation(-Vec3::X * 10.0) * Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0)),
    ));
    let quad = common::quad(Vec3::new(20.0, 0.0, 0.0), Vec3::X, Vec3::Y, 0);
    s.add_mesh(quad, Mat4::IDENTITY);
    s
}

/// A ray straight down −z onto the plane z = 0 at (x, y), from z = 10.
fn down(x: f32, y: f32) -> Ray {
    Ray::new(Vec3::new(x, y, 10.0), -Vec3::Z)
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() < 1e-5
}

#[test]
fn triangles_know_their_instance() {
    let s = scene();
    let g = SceneGeometry::build(&s, BuildQuality::Fast).unwrap();
    assert_eq!(g.triangles.len(), 5);
    for (instance, range) in [(0, 0..1), (1, 1..2), (2, 2..3), (3, 3..5), (4, 5..5)] {
        assert_eq!(g.instance_triangles(instance), range, "instance {instance}");
    }
    assert_eq!(g.triangle_source(4), (3, 1));
    assert_eq!(g.triangle_source(2), (2, 0));
    // An instance's own material overrides its mesh's.
    let materials: Vec<usize> = (0..5).map(|t| g.material_of(t)).collect();
    assert_eq!(materials, [0, 1, 0, 0, 0]);
    // World vertices: instance 1 stretched and moved, 2 mirrored.
    assert_eq!(g.triangles[1][1], Vec3::new(14.0, 0.0, 0.0));
    assert_eq!(g.triangles[2][1], Vec3::new(-12.0, 0.0, 0.0));
}

/// The front normal's length is twice the area; a mirroring transform
/// reverses the winding, and the front stays where it was (+z).
#[test]
fn front_faces_and_areas() {
    let g = SceneGeometry::build(&scene(), BuildQuality::Fast).unwrap();
    assert_eq!(g.front_normal_scaled(0), Vec3::new(0.0, 0.0, 6.0));
    assert_eq!(g.front_normal_scaled(1), Vec3::new(0.0, 0.0, 12.0));
    assert_eq!(g.front_normal_scaled(2), Vec3::new(0.0, 0.0, 6.0));
    let areas: Vec<f32> = (0..5).map(|t| g.area(t)).collect();
    assert_eq!(areas, [3.0, 6.0, 3.0, 0.5, 0.5]);
}

/// Everything a hit reports, at b = (1/4, 1/2).
#[test]
fn a_hit_reports_its_surface() {
    let s = scene();
    let g = SceneGeometry::build(&s, BuildQuality::Fast).unwrap();
    let h = g.intersect(&s, &down(0.5, 1.5)).expect("a hit");
    assert_eq!((h.triangle, h.light, h.material), (0, None, 0));
    assert!((h.t - 10.0).abs() < 1e-5 && (h.b1 - B1).abs() < 1e-6 && (h.b2 - B2).abs() < 1e-6);
    assert!(close(h.p, Vec3::new(0.5, 1.5, 0.0)), "{}", h.p);
    assert_eq!(h.ng, Vec3::Z);
    // (1/4)(0,0,1) + (1/4)(0,0,1) + (1/2)(1,0,1) = (½, 0, 1).
    assert!(
        close(h.ns, Vec3::new(0.5, 0.0, 1.0).normalize()),
        "{}",
        h.ns
    );
    assert!(close(h.uvs[0].extend(0.0), Vec3::new(B1, B2, 0.0)));
    assert!(close(
        h.uvs[1].extend(0.0),
        Vec3::new(2.0 * B1, 2.0 * B2, 0.0)
    ));
    assert!(close(h.color, Vec3::new(0.25, 0.25, 0.5)), "{}", h.color);

    // Stretched ×2 in x: the same barycentrics at x = 10 + 4/4 = 11; the
    // normal matrix (inverse transpose, diag(½, 1, 1)) halves normals' x.
    let h = g.intersect(&s, &down(11.0, 1.5)).expect("a hit");
    assert_eq!((h.triangle, h.material), (1, 1));
    assert!((h.b1 - B1).abs() < 1e-6 && (h.b2 - B2).abs() < 1e-6);
    assert!(
        close(h.ns, Vec3::new(0.25, 0.0, 1.0).normalize()),
        "{}",
        h.ns
    );

    // Mirrored: x → −x, so the normal's x turns too; the front stays +z.
    let h = g.intersect(&s, &down(-10.5, 1.5)).expect("a hit");
    assert_eq!(h.triangle, 2);
    assert_eq!(h.ng, Vec3::Z);
    assert!(
        close(h.ns, Vec3::new(-0.5, 0.0, 1.0).normalize()),
        "{}",
        h.ns
    );

    // No vertex normals or colours: the shading normal is the geometric
    // one and the colour is white; the quad's UVs, set 1 the barycentrics.
    let h = g.intersect(&s, &down(20.75, 0.25)).expect("a hit");
    assert_eq!((h.triangle, h.ns, h.color), (3, Vec3::Z, Vec3::ONE));
    assert!(close(h.uvs[0].extend(0.0), Vec3::new(0.75, 0.25, 0.0)));
    assert!(close(h.uvs[1].extend(0.0), Vec3::new(h.b1, h.b2, 0.0)));

    // The same surface at t = 0 where a query starts on it.
    let p = g.surface_point(&s, 0, B1, B2);
    assert_eq!((p.t, p.triangle, p.light), (0.0, 0, None));
    assert!(
        close(p.p, Vec3::new(0.5, 1.5, 0.0)) && close(p.ns, Vec3::new(0.5, 0.0, 1.0).normalize())
    );
}

/// Shading normals turn to the front face's side; a zero one is replaced
/// by the geometric normal.
#[test]
fn shading_normals_face_the_front() {
    let mut s = Scene::default();
    s.add_material(Material::lambert("a", Rgb::splat(0.5)));
    let mut back = triangle(0);
    back.normals = Some(vec![Vec3::new(0.0, 0.0, -1.0); 3]);
    s.add_mesh(back, Mat4::IDENTITY);
    let mut zero = triangle(0);
    zero.normals = Some(vec![Vec3::ZERO; 3]);
    s.add_mesh(zero, Mat4::from_translation(Vec3::X * 10.0));
    let g = SceneGeometry::build(&s, BuildQuality::Fast).unwrap();
    for x in [0.5, 10.5] {
        let h = g.intersect(&s, &down(x, 1.5)).expect("a hit");
        assert_eq!((h.ng, h.ns), (Vec3::Z, Vec3::Z), "x = {x}");
    }
    // Seen from below the ray meets the back face: the normals are still
    // the front's.
    let up = Ray::new(Vec3::new(0.5, 1.5, -10.0), Vec3::Z);
    let h = g.intersect(&s, &up).expect("a hit");
    assert_eq!((h.ng, h.ns), (Vec3::Z, Vec3::Z));
}

/// UV sets at barycentrics, and A_uv / A_world per set.
#[test]
fn uvs_and_their_area_ratios() {
    let s = scene();
    let g = SceneGeometry::build(&s, BuildQuality::Fast).unwrap();
    let [u0, u1] = g.uvs_at(&s, 1, B1, B2);
    assert_eq!((u0, u1), (Vec2::new(B1, B2), Vec2::new(0.5, 1.0)));
    // Triangle 0: world area 3, UV areas ½ and 2; stretched: world area 6.
    let ratios = |t| g.uv_area_ratio(&s, t);
    assert_eq!(ratios(0), [0.5 / 3.0, 2.0 / 3.0]);
    assert_eq!(ratios(1), [0.5 / 6.0, 2.0 / 6.0]);
    assert_eq!(ratios(2), [0.5 / 3.0, 2.0 / 3.0]);
    // The quad's triangles: UV area ½ in set 0 (a unit square's half); set
    // 1 missing: the barycentric corners, area ½; world area ½.
    assert_eq!(ratios(3), [1.0, 1.0]);
    assert_eq!(ratios(4), [1.0, 1.0]);
    // Clockwise UVs count by their size, not their sign; degenerate UVs
    // give 0.
    let mut s2 = Scene::default();
    s2.add_material(Material::lambert("a", Rgb::splat(0.5)));
    let mut flipped = triangle(0);
    flipped.uv0 = Some(vec![Vec2::ZERO, Vec2::Y, Vec2::X]);
    flipped.uv1 = Some(vec![Vec2::ZERO, Vec2::X, Vec2::X * 3.0]);
    s2.add_mesh(flipped, Mat4::IDENTITY);
    let g2 = SceneGeometry::build(&s2, BuildQuality::Fast).unwrap();
    assert_eq!(g2.uv_area_ratio(&s2, 0), [0.5 / 3.0, 0.0]);
}

/// Tangents interpolate, go through the transform (not the normal
/// matrix), and their handedness flips under mirroring.
#[test]
fn tangents_in_world_space() {
    let s = scene();
    let g = SceneGeometry::build(&s, BuildQuality::Fast).unwrap();
    // (1/4)(1,0,0) + (1/4)(1,0,0) + (1/2)(0,1,0) = (½, ½, 0), w = +1.
    assert_eq!(
        g.tangent_at(&s, 0, B1, B2),
        Some(Vec4::new(0.5, 0.5, 0.0, 1.0))
    );
    assert_eq!(
        g.tangent_at(&s, 1, B1, B2),
        Some(Vec4::new(1.0, 0.5, 0.0, 1.0))
    );
    assert_eq!(
        g.tangent_at(&s, 2, B1, B2),
        Some(Vec4::new(-0.5, 0.5, 0.0, -1.0))
    );
    assert_eq!(g.tangent_at(&s, 3, B1, B2), None);
    // Vertex 0's handedness decides: −1 there gives −1 (+1 when mirrored).
    let mut s2 = scene();
    s2.meshes[0].tangents.as_mut().unwrap()[0].w = -1.0;
    let g2 = SceneGeometry::build(&s2, BuildQuality::Fast).unwrap();
    assert_eq!(g2.tangent_at(&s2, 0, B1, B2).unwrap().w, -1.0);
    assert_eq!(g2.tangent_at(&s2, 2, B1, B2).unwrap().w, 1.0);
}

fn sphere_light(center: Vec3, radius: f32) -> SceneAreaLight {
    common::area_light("sphere", Shape::Sphere { center, radius }, 1.0)
}

/// Analytic area lights and triangles: the nearest wins, whichever is
/// listed first; nothing is seen or blocks past `tmax`.
#[test]
fn area_lights_against_triangles() {
    let mut s = scene();
    // Listed first but farther: the ray from z = 10 enters it at t = 6.5.
    s.area_lights
        .push(sphere_light(Vec3::new(0.5, 1.5, 3.0), 0.5));
    // Nearer: entered at t = 4, at (0.5, 1.5, 6).
    s.area_lights
        .push(sphere_light(Vec3::new(0.5, 1.5, 5.0), 1.0));
    // Behind the triangle: never seen from above.
    s.area_lights
        .push(sphere_light(Vec3::new(11.0, 1.5, -5.0), 1.0));
    let g = SceneGeometry::build(&s, BuildQuality::Fast).unwrap();
    let h = g.intersect(&s, &down(0.5, 1.5)).expect("a hit");
    assert_eq!((h.light, h.triangle), (Some(1), u32::MAX));
    assert!((h.t - 4.0).abs() < 1e-5 && close(h.p, Vec3::new(0.5, 1.5, 6.0)));
    assert_eq!((h.ng, h.ns, h.color), (Vec3::Z, Vec3::Z, Vec3::ONE));
    assert_eq!((h.b1, h.b2, h.uvs), (0.0, 0.0, [Vec2::ZERO; 2]));
    // Past the lights, the triangle in front of the third one.
    let h = g.intersect(&s, &down(11.0, 1.5)).expect("a hit");
    assert_eq!((h.light, h.triangle), (None, 1));
    // The second light alone: a ray that ends before it sees nothing.
    let short = |tmax| Ray::segment(Vec3::new(0.5, 1.5, 10.0), -Vec3::Z, tmax);
    assert!(g.intersect(&s, &short(3.9)).is_none());
    assert!(!g.occluded(&short(3.9)));
    assert!(g.occluded(&short(4.1)));
    // Triangles alone block too, within tmax only.
    let past = |tmax| Ray::segment(Vec3::new(20.25, 0.75, 10.0), -Vec3::Z, tmax);
    assert!(!g.occluded(&past(9.9)));
    assert!(g.occluded(&past(10.1)));
    assert_eq!(g.intersect(&s, &past(10.1)).map(|h| h.triangle), Some(4));
}

/// A camera ray passes through culled back faces within its own length:
/// after a face at t = 2 it has 3 of its 5 left, so a face at 4.8 is seen
/// (at t = 4.8 from the camera) and one at 5.2 is not.
#[test]
fn camera_segments_keep_their_length_through_culled_faces() {
    for (far, seen) in [(4.8, true), (5.2, false)] {
        let mut s = Scene::default();
        let culled = s.add_material(Material {
            cull_back_faces: true,
            ..Material::lambert("one-sided", Rgb::splat(0.5))
        });
        let plain = s.add_material(Material::lambert("plain", Rgb::splat(0.5)));
        // The ray goes −z from z = 10: the first quad faces −z (its back
        // is met, and culled), the second +z.
        let back = common::quad(
            Vec3::new(-1.0, -1.0, 8.0),
            Vec3::Y * 2.0,
            Vec3::X * 2.0,
            culled,
        );
        s.add_mesh(back, Mat4::IDENTITY);
        let front = common::quad(
            Vec3::new(-1.0, -1.0, 10.0 - far),
            Vec3::X * 2.0,
            Vec3::Y * 2.0,
            plain,
        );
        s.add_mesh(front, Mat4::IDENTITY);
        let g = SceneGeometry::build(&s, BuildQuality::Fast).unwrap();
        let ray = Ray::segment(Vec3::new(0.1, 0.2, 10.0), -Vec3::Z, 5.0);
        let hit = g.intersect_camera(&s, &ray);
        assert_eq!(hit.is_some(), seen, "far face at t = {far}");
        if let Some(h) = hit {
            assert_eq!(h.material, plain);
            assert!((h.t - far).abs() < 1e-5, "t = {}", h.t);
        }
        // Without the culling the first face is what the camera sees.
        let h = g.intersect(&s, &ray).expect("the one-sided face");
        assert!((h.t - 2.0).abs() < 1e-5);
    }
}

/// A scene of `instances` placements of a 2²⁰-triangle mesh (one triangle
/// repeated), less `fewer` triangles in the last placement's own mesh:
/// 12 MB of indices whatever the count, for the BVH's limit.
fn placed_many_times(instances: usize, fewer: usize) -> Scene {
    let mut s = Scene::default();
    let mesh = |n: usize| Mesh {
        indices: vec![[0, 1, 2]; n],
        ..triangle(0)
    };
    let big = s.add_mesh(mesh(1 << 20), Mat4::IDENTITY);
    for _ in 2..instances {
        s.instances.push(Instance::new(big, Mat4::IDENTITY));
    }
    s.add_mesh(mesh((1 << 20) - fewer), Mat4::IDENTITY);
    s
}

/// 2²⁷ triangles, one more than the BVH holds (2²⁷ − 1): `render` and
/// `SceneGeometry::build` return the error with the count, at once and
/// without building anything; at exactly the limit the size check passes.
#[test]
fn a_scene_past_the_bvh_limit_is_an_error() {
    use penumbra_trace::{RenderOptions, SceneTooLarge, render};
    let over = placed_many_times(128, 0);
    let expected = SceneTooLarge { triangles: 1 << 27 };
    assert_eq!(SceneGeometry::check_size(&over), Err(expected));
    assert_eq!(
        SceneGeometry::build(&over, BuildQuality::Fast).err(),
        Some(expected)
    );
    let settings = over.settings.clone();
    assert_eq!(
        render(&over, &settings, &RenderOptions::default()).err(),
        Some(expected)
    );
    assert_eq!(
        expected.to_string(),
        "134217728 triangles with every instance counted; penumbra's BVH holds at most 134217727"
    );
    let at_limit = placed_many_times(128, 1);
    assert_eq!(at_limit.triangle_count(), (1 << 27) - 1);
    assert_eq!(SceneGeometry::check_size(&at_limit), Ok(()));
}
