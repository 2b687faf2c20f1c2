//! Light selection and sampling for the integrators: the scene's abstract
//! lights, its analytic area lights (sphere, disk, quad), every emissive
//! triangle and the environment, chosen in proportion to emitted power.

use crate::geometry::SceneGeometry;
use glam::Vec3;
use penumbra_scene::Scene;
use penumbra_shading::Rgb;
use penumbra_shading::color::luminance;
use penumbra_shading::light::{Environment, LightSample};
use penumbra_shading::sampling::Distribution1D;
use penumbra_shading::sampling::square_to_triangle;

/// One selectable light.
#[derive(Clone, Copy, Debug)]
enum Entry {
    /// Index into `Scene::lights`.
    Abstract(usize),
    /// Emissive triangle (index in [`SceneGeometry`]).
    Triangle {
        triangle: u32,
        /// Its material, whose emission (with its texture) is the radiance.
        material: usize,
        double_sided: bool,
        /// Area and unit front normal, computed once.
        area: f32,
        normal: Vec3,
    },
    /// Analytic area light (index into `Scene::area_lights`).
    Shape(usize),
    /// The environment (constant or map).
    Environment,
}

/// A sampled light with the probability of having chosen it.
#[derive(Clone, Copy, Debug)]
pub struct ChosenLight {
    pub sample: LightSample,
    /// Probability of having selected this light; `sample.value` does not
    /// include it, so estimators divide by it.
    pub select_pdf: f32,
    /// The sampler's entry that was chosen (see [`LightSampler::source`]).
    pub entry: usize,
}

/// Where an emitted contribution came from, as the integrators know it
/// (cheap to make; [`LightSampler::source`] names the light).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Emitter {
    /// A light chosen by next-event estimation (a sampler entry).
    Entry(usize),
    /// An emissive triangle (index in [`SceneGeometry`]) hit by a ray.
    Triangle(u32),
    /// An analytic area light (index into `Scene::area_lights`) hit by a ray.
    Shape(u32),
    /// The environment, reached by an escaping ray.
    Environment,
}

/// A light of the scene as a user names it: what per-light light maps are
/// split by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum LightSource {
    /// `Scene::lights[i]` (point, directional, spot).
    Light(usize),
    /// `Scene::area_lights[i]` (sphere, disk, quad).
    AreaLight(usize),
    /// The emissive triangles of `Scene::instances[i]`.
    EmissiveInstance(usize),
    /// The environment (constant background or map).
    Environment,
}

#[derive(Debug)]
pub struct LightSampler {
    entries: Vec<Entry>,
    /// All lights, by power.
    all: Distribution1D,
    /// Indices (into `entries`) of the area lights, and their distribution.
    area_entries: Vec<usize>,
    area: Distribution1D,
    /// For each geometry triangle: its entry index, or u32::MAX.
    entry_of_triangle: Vec<u32>,
    /// Entry index of each analytic area light (u32::MAX if it emits nothing).
    entry_of_shape: Vec<u32>,
    /// Entry index of the environment, if it emits.
    environment_entry: Option<usize>,
    environment: Environment,
}

impl LightSampler {
    pub fn new(scene: &Scene, geometry: &SceneGeometry) -> Self {
        // Scene radius over the meshes and the analytic area lights.
        let radius = scene
            .bounds()
            .map_or(1.0, |(lo, hi)| 0.5 * (hi - lo).length())
            .max(1e-3);
        let mut entries = Vec::new();
        let mut weights = Vec::new();
        for (i, l) in scene.lights.iter().enumerate() {
            entries.push(Entry::Abstract(i));
            weights.push(luminance(l.light.power(radius)));
        }
        let mut entry_of_triangle = vec![u32::MAX; geometry.triangles.len()];
        let mut area_entries = Vec::new();
        for t in 0..geometry.triangles.len() as u32 {
            let m = &scene.materials[geometry.material_of(t)];
            if !m.is_emissive() {
                continue;
            }
            let area = geometry.area(t);
            let mut w = luminance(m.emitted_power(area));
            if let Some(tex) = m.emission_texture {
                w *= luminance(mean_texture_over_triangle(scene, geometry, t, tex));
            }
            if w <= 0.0 || !w.is_finite() {
                continue;
            }
            entry_of_triangle[t as usize] = entries.len() as u32;
            area_entries.push(entries.len());
            let normal = geometry.front_normal_scaled(t).normalize_or_zero();
            entries.push(Entry::Triangle {
                triangle: t,
                material: geometry.material_of(t),
                double_sided: m.double_sided,
                area,
                normal,
            });
            weights.push(w);
        }
        let mut entry_of_shape = vec![u32::MAX; scene.area_lights.len()];
        for (i, l) in scene.area_lights.iter().enumerate() {
            let w = luminance(l.light.power());
            if w > 0.0 && w.is_finite() {
                entry_of_shape[i] = entries.len() as u32;
                area_entries.push(entries.len());
                entries.push(Entry::Shape(i));
                weights.push(w);
            }
        }
        let environment = scene.environment();
        let mut environment_entry = None;
        let w = luminance(environment.power(radius));
        if w > 0.0 && w.is_finite() {
            environment_entry = Some(entries.len());
            area_entries.push(entries.len());
            entries.push(Entry::Environment);
            weights.push(w);
        }
        let area = Distribution1D::new(area_entries.iter().map(|&e| weights[e]));
        let all = Distribution1D::new(weights);
        Self {
            entries,
            all,
            area_entries,
            area,
            entry_of_triangle,
            entry_of_shape,
            environment_entry,
            environment,
        }
    }

    /// Where every light the sampler chooses is an emissive triangle (no
    /// abstract or analytic area light, no emitting environment): each
    /// choice's triangle, in [`Self::sample`]'s order, and the
    /// distribution it picks them by. `None` otherwise.
    pub(crate) fn triangle_lights(&self) -> Option<(Vec<u32>, &Distribution1D)> {
        let triangles = self
            .entries
            .iter()
            .map(|e| match *e {
                Entry::Triangle { triangle, .. } => Some(triangle),
                _ => None,
            })
            .collect::<Option<Vec<u32>>>()?;
        Some((triangles, &self.all))
    }

    /// The environment (what escaping rays see).
    pub fn environment(&self) -> &Environment {
        &self.environment
    }

    pub fn is_empty(&self) -> bool {
        self.all.is_empty()
    }

    /// Picks a light by power and samples it from `p`.
    pub fn sample(
        &self,
        scene: &Scene,
        geometry: &SceneGeometry,
        p: Vec3,
        u_select: f32,
        u: [f32; 2],
    ) -> Option<ChosenLight> {
        let (i, select_pdf) = self.all.sample(u_select)?;
        let sample = self.sample_entry(scene, geometry, i, p, u)?;
        Some(ChosenLight {
            sample,
            select_pdf,
            entry: i,
        })
    }

    /// Picks a light with extent (emissive triangle, analytic area light or
    /// environment) by power (the `local` integrator treats abstract lights
    /// exactly and needs only these sampled).
    pub fn sample_area(
        &self,
        scene: &Scene,
        geometry: &SceneGeometry,
        p: Vec3,
        u_select: f32,
        u: [f32; 2],
    ) -> Option<ChosenLight> {
        let (k, select_pdf) = self.area.sample(u_select)?;
        let entry = self.area_entries[k];
        let sample = self.sample_entry(scene, geometry, entry, p, u)?;
        Some(ChosenLight {
            sample,
            select_pdf,
            entry,
        })
    }

    /// The scene light behind a contribution; `None` for an emitter hit
    /// that is not one of the sampler's lights (it emits no power).
    pub fn source(&self, geometry: &SceneGeometry, emitter: Emitter) -> Option<LightSource> {
        let entry = match emitter {
            Emitter::Entry(e) => e,
            Emitter::Triangle(t) => {
                return (self.entry_of_triangle.get(t as usize) != Some(&u32::MAX))
                    .then(|| LightSource::EmissiveInstance(geometry.triangle_source(t).0));
            }
            Emitter::Shape(l) => return Some(LightSource::AreaLight(l as usize)),
            Emitter::Environment => return Some(LightSource::Environment),
        };
        Some(match *self.entries.get(entry)? {
            Entry::Abstract(i) => LightSource::Light(i),
            Entry::Shape(i) => LightSource::AreaLight(i),
            Entry::Environment => LightSource::Environment,
            Entry::Triangle { triangle, .. } => {
                LightSource::EmissiveInstance(geometry.triangle_source(triangle).0)
            }
        })
    }

    /// Every light the sampler can choose, each once, in a fixed order
    /// (abstract lights, emissive instances, area lights, environment).
    pub fn sources(&self, geometry: &SceneGeometry) -> Vec<LightSource> {
        let mut out: Vec<LightSource> = (0..self.entries.len())
            .filter_map(|e| self.source(geometry, Emitter::Entry(e)))
            .collect();
        out.sort();
        out.dedup();
        out
    }

    fn sample_entry(
        &self,
        scene: &Scene,
        geometry: &SceneGeometry,
        i: usize,
        p: Vec3,
        u: [f32; 2],
    ) -> Option<LightSample> {
        match self.entries[i] {
            Entry::Abstract(l) => scene.lights[l].light.sample_li(p),
            Entry::Shape(l) => geometry.area_lights[l].sample_li(p, u),
            Entry::Environment => self.environment.sample_li(u),
            Entry::Triangle {
                triangle,
                material,
                double_sided,
                area,
                normal: n,
            } => {
                let [a, b, c] = geometry.triangles[triangle as usize];
                let bary = square_to_triangle(u);
                // The emission (texture) at the sampled point: the triangle
                // is picked by its mean, the point uniformly by area, and
                // the estimate divides by that density, so it stays unbiased.
                let m = &scene.materials[material];
                let radiance = match m.emission_texture {
                    Some(_) => {
                        let uvs = geometry.uvs_at(scene, triangle, bary.x, bary.y);
                        m.emission_at(&scene.textures, uvs)
                    }
                    None => m.emission,
                };
                let q = a * (1.0 - bary.x - bary.y) + b * bary.x + c * bary.y;
                let d = q - p;
                let dist2 = d.length_squared();
                if dist2 <= 0.0 || area <= 0.0 {
                    return None;
                }
                let dist = dist2.sqrt();
                let wi = d / dist;
                let cos_light = -wi.dot(n);
                if cos_light <= 0.0 && !double_sided {
                    return None;
                }
                let cos_light = cos_light.abs();
                if cos_light <= 1e-7 {
                    return None;
                }
                // Area density 1/A → solid angle: pdf = d² / (A |cos θl|).
                let pdf = dist2 / (area * cos_light);
                Some(LightSample {
                    wi,
                    distance: dist,
                    value: radiance / pdf,
                    pdf,
                    is_delta: false,
                })
            }
        }
    }

    /// Solid-angle pdf with which [`LightSampler::sample`] would pick the
    /// point `q` on emissive `triangle` (normal `ng`) from `p`, including
    /// the selection probability. 0 for non-emitters.
    pub fn pdf_triangle(&self, triangle: u32, p: Vec3, q: Vec3, ng: Vec3) -> f32 {
        let e = self.entry_of_triangle[triangle as usize];
        if e == u32::MAX {
            return 0.0;
        }
        let d = q - p;
        let dist2 = d.length_squared();
        let cos = (d.normalize_or_zero().dot(ng)).abs();
        if cos <= 1e-7 {
            return 0.0;
        }
        let Entry::Triangle { area, .. } = self.entries[e as usize] else {
            return 0.0;
        };
        self.all.pmf(e as usize) * dist2 / (area * cos)
    }

    /// Solid-angle pdf with which [`LightSampler::sample`] would produce
    /// direction `wi` from `p` towards analytic area light `light` (index
    /// into `Scene::area_lights`), including the selection probability.
    pub fn pdf_area_light(&self, geometry: &SceneGeometry, light: u32, p: Vec3, wi: Vec3) -> f32 {
        let e = self.entry_of_shape[light as usize];
        if e == u32::MAX {
            return 0.0;
        }
        self.all.pmf(e as usize) * geometry.area_lights[light as usize].pdf_li(p, wi)
    }

    /// Solid-angle pdf with which [`LightSampler::sample`] would produce the
    /// environment direction `wi`, including the selection probability.
    pub fn pdf_environment(&self, wi: Vec3) -> f32 {
        match self.environment_entry {
            Some(e) => self.all.pmf(e) * self.environment.pdf(wi),
            None => 0.0,
        }
    }
}

/// Stratified points per axis for [`mean_texture_over_triangle`].
const TEXTURE_MEAN_GRID: u32 = 4;

/// The mean of emission texture `tex` over `triangle`, from a 4×4 grid of
/// points spread uniformly over it (`square_to_triangle` of the cell
/// centres): the weight with which the triangle is picked as a light. A
/// triangle whose texture is black there is never picked; rays that hit it
/// still see its emission.
fn mean_texture_over_triangle(
    scene: &Scene,
    geometry: &SceneGeometry,
    triangle: u32,
    tex: usize,
) -> Rgb {
    let n = TEXTURE_MEAN_GRID;
    let mut sum = Rgb::ZERO;
    for i in 0..n {
        for j in 0..n {
            let u = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
            let b = square_to_triangle(u);
            sum += scene.textures[tex].lookup(geometry.uvs_at(scene, triangle, b.x, b.y));
        }
    }
    sum / (n * n) as f32
}

/// Radiance emitted by material emission `le` towards direction `wo` from a
/// surface with front normal `ng` (front side only unless double-sided).
pub fn emitted(le: Rgb, double_sided: bool, ng: Vec3, wo: Vec3) -> Rgb {
    if double_sided || ng.dot(wo) > 0.0 {
        le
    } else {
        Rgb::ZERO
    }
}
