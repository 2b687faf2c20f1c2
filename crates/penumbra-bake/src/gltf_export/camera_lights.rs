//! The scene's camera and its punctual lights (`KHR_lights_punctual`).

use super::*;

impl Builder<'_> {
    pub(super) fn camera(&mut self, cam: &Camera) {
        let s = &self.scene.settings;
        let aspect = if s.width > 0 && s.height > 0 {
            s.width as f32 / s.height as f32
        } else {
            1.0
        };
        // glTF cameras need clip planes; penumbra traces rays without them.
        let reach = self.scene.bounds().map_or(1.0, |(lo, hi)| {
            let p = cam.position();
            let mut far = (hi - lo).length();
            for k in 0..8 {
                let c = Vec3::new(
                    if k & 1 == 0 { lo.x } else { hi.x },
                    if k & 2 == 0 { lo.y } else { hi.y },
                    if k & 4 == 0 { lo.z } else { hi.z },
                );
                far = far.max((c - p).length());
            }
            far
        });
        let reach = if reach.is_finite() && reach > 0.0 {
            reach
        } else {
            1.0
        };
        let camera = match cam.projection {
            Projection::Perspective { fov_y } => json!({
                "type": "perspective",
                "perspective": {
                    "yfov": num(fov_y),
                    "aspectRatio": num(aspect),
                    "znear": num(reach * 1e-4),
                },
            }),
            Projection::Orthographic { height } => json!({
                "type": "orthographic",
                "orthographic": {
                    "xmag": num(0.5 * height * aspect),
                    "ymag": num(0.5 * height),
                    "znear": 0.0,
                    "zfar": num(2.0 * reach),
                },
            }),
        };
        self.cameras.push(camera);
        let (_, r, t) = cam.camera_to_world.to_scale_rotation_translation();
        let mut node = Map::new();
        node.insert("name".into(), json!("camera"));
        node.insert("camera".into(), json!(self.cameras.len() - 1));
        trs_json(&mut node, t, r.normalize(), Vec3::ONE);
        self.nodes.push(Value::Object(node));
    }

    /// A punctual light (KHR_lights_punctual): intensity in cd or lux, the
    /// inverse of penumbra's loader.
    pub(super) fn light(&mut self, l: usize) {
        let scene = self.scene;
        let sl = &scene.lights[l];
        let split = |c: Rgb| {
            let m = c.max_element();
            if m > 0.0 && m.is_finite() {
                (c / m, m * LUMENS_PER_WATT)
            } else {
                (Rgb::ONE, 0.0)
            }
        };
        let range = |r: f32| (r.is_finite() && r > 0.0).then_some(r);
        let aim = |d: Vec3| Quat::from_rotation_arc(-Vec3::Z, d.normalize_or(-Vec3::Z));
        let (mut light, position, rotation) = match sl.light {
            Light::Point(p) => {
                let (color, cd) = split(p.intensity);
                let mut v = json!({"type": "point", "color": rgb(color), "intensity": num(cd)});
                if let Some(r) = range(p.range) {
                    v["range"] = num(r);
                }
                (v, p.position, Quat::IDENTITY)
            }
            Light::Directional(d) => {
                let (color, lux) = split(d.irradiance);
                let v = json!({"type": "directional", "color": rgb(color), "intensity": num(lux)});
                (v, Vec3::ZERO, aim(d.direction))
            }
            Light::Spot(s) => {
                let (color, cd) = split(s.intensity);
                let half_pi = std::f32::consts::FRAC_PI_2;
                let outer = s.cos_outer.clamp(-1.0, 1.0).acos().clamp(1e-4, half_pi);
                let mut inner = s.cos_inner.clamp(-1.0, 1.0).acos().clamp(0.0, outer);
                if inner >= outer {
                    inner = outer * 0.999;
                }
                if (s.cos_outer.acos() - outer).abs() > 1e-6 {
                    self.warnings.push(format!(
                        "spot light '{}': cone angle clamped to glTF's (0, 90°]",
                        sl.name
                    ));
                }
                let mut v = json!({
                    "type": "spot",
                    "color": rgb(color),
                    "intensity": num(cd),
                    "spot": {"innerConeAngle": num(inner), "outerConeAngle": num(outer)},
                });
                if let Some(r) = range(s.range) {
                    v["range"] = num(r);
                }
                (v, s.position, aim(s.direction))
            }
        };
        light["name"] = json!(sl.name);
        self.lights.push(light);
        self.extensions_used.insert("KHR_lights_punctual".into());
        let mut node = Map::new();
        node.insert("name".into(), json!(sl.name));
        trs_json(&mut node, position, rotation, Vec3::ONE);
        node.insert(
            "extensions".into(),
            json!({"KHR_lights_punctual": {"light": self.lights.len() - 1}}),
        );
        self.nodes.push(Value::Object(node));
    }
}
