//! The GLB container: buffer views, accessors, images and textures in the
//! binary chunk, the JSON document, and the 12-byte header.

use super::*;

/// Linear → sRGB transfer, 8 bits.
pub(super) fn srgb8(x: f32) -> u8 {
    let x = if x.is_finite() {
        x.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let s = if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

/// Linear value, 8 bits (no transfer function).
pub(super) fn linear8(x: f32) -> u8 {
    let x = if x.is_finite() {
        x.clamp(0.0, 1.0)
    } else {
        0.0
    };
    (x * 255.0).round() as u8
}

impl Builder<'_> {
    /// Appends `bytes` as a new buffer view (4-byte aligned).
    pub(super) fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut v = json!({
            "buffer": 0,
            "byteOffset": self.bin.len(),
            "byteLength": bytes.len(),
        });
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.buffer_views.push(v);
        self.buffer_views.len() - 1
    }

    /// A float accessor of `type_` ("VEC2", "VEC3") over `data`; with
    /// `bounds`, its exact min/max.
    pub(super) fn float_accessor(
        &mut self,
        data: &[f32],
        type_: &str,
        comps: usize,
        bounds: bool,
    ) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(ARRAY_BUFFER));
        let mut a = json!({
            "bufferView": view,
            "componentType": FLOAT,
            "count": data.len() / comps,
            "type": type_,
        });
        if bounds {
            let mut lo = vec![f32::INFINITY; comps];
            let mut hi = vec![f32::NEG_INFINITY; comps];
            for v in data.chunks_exact(comps) {
                for k in 0..comps {
                    lo[k] = lo[k].min(v[k]);
                    hi[k] = hi[k].max(v[k]);
                }
            }
            // Exact values (not shortest decimals): the validator compares
            // them with the data.
            a["min"] = Value::from(lo.iter().map(|&x| x as f64).collect::<Vec<_>>());
            a["max"] = Value::from(hi.iter().map(|&x| x as f64).collect::<Vec<_>>());
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// An index accessor: 16 bits when every index fits below the
    /// primitive-restart value, else 32.
    pub(super) fn index_accessor(&mut self, triangles: &[[u32; 3]], vertices: usize) -> usize {
        let flat = triangles.iter().flatten();
        let (bytes, ctype): (Vec<u8>, u32) = if vertices < 0xffff {
            (
                flat.flat_map(|&i| (i as u16).to_le_bytes()).collect(),
                UNSIGNED_SHORT,
            )
        } else {
            (flat.flat_map(|&i| i.to_le_bytes()).collect(), UNSIGNED_INT)
        };
        let view = self.view(&bytes, Some(ELEMENT_ARRAY_BUFFER));
        self.accessors.push(json!({
            "bufferView": view,
            "componentType": ctype,
            "count": triangles.len() * 3,
            "type": "SCALAR",
        }));
        self.accessors.len() - 1
    }

    /// An 8-bit RGB PNG embedded as an image; returns the image index.
    pub(super) fn png_image(
        &mut self,
        name: &str,
        w: u32,
        h: u32,
        rgb8: &[u8],
    ) -> Result<usize, BakeError> {
        let mut png = Vec::new();
        image::codecs::png::PngEncoder::new(&mut png)
            .write_image(rgb8, w, h, image::ExtendedColorType::Rgb8)
            .map_err(|e| {
                BakeError::file(self.path, format!("cannot encode the PNG of {name}: {e}"))
            })?;
        let view = self.view(&png, None);
        self.images.push(json!({
            "name": name,
            "bufferView": view,
            "mimeType": "image/png",
        }));
        Ok(self.images.len() - 1)
    }

    pub(super) fn sampler(&mut self, clamp: bool) -> usize {
        let slot = if clamp {
            self.clamp_sampler
        } else {
            self.repeat_sampler
        };
        if let Some(s) = slot {
            return s;
        }
        let wrap = if clamp { CLAMP_TO_EDGE } else { REPEAT };
        self.samplers.push(json!({
            "magFilter": LINEAR,
            "minFilter": LINEAR,
            "wrapS": wrap,
            "wrapT": wrap,
        }));
        let s = self.samplers.len() - 1;
        if clamp {
            self.clamp_sampler = Some(s);
        } else {
            self.repeat_sampler = Some(s);
        }
        s
    }

    /// The texture of atlas page `page`'s kA (linear, R = G = B).
    pub(super) fn page_texture(&mut self, page: u32) -> Result<usize, BakeError> {
        if let Some(&t) = self.page_textures.get(&page) {
            return Ok(t);
        }
        let bake = self.bake;
        let img = &bake.maps[0].pages[page as usize];
        let data: Vec<u8> = img.pixels.iter().flat_map(|p| [linear8(p.x); 3]).collect();
        let name = format!("ambient occlusion (atlas page {page})");
        let image = self.png_image(&name, img.width, img.height, &data)?;
        let sampler = self.sampler(true);
        self.textures.push(json!({
            "name": name,
            "source": image,
            "sampler": sampler,
        }));
        let t = self.textures.len() - 1;
        self.page_textures.insert(page, t);
        Ok(t)
    }

    /// The glTF texture of scene texture `id`, sRGB-encoded (colour) or
    /// linear (data); `None` for an empty texture.
    pub(super) fn scene_texture(
        &mut self,
        id: usize,
        srgb: bool,
    ) -> Result<Option<usize>, BakeError> {
        if let Some(&t) = self.scene_textures.get(&(id, srgb)) {
            return Ok(Some(t));
        }
        let scene = self.scene;
        let tex: &Texture = &scene.textures[id];
        if tex.width == 0
            || tex.height == 0
            || tex.texels.len() != (tex.width * tex.height) as usize
        {
            self.warnings.push(format!(
                "texture '{}' is empty and is not exported",
                tex.name
            ));
            return Ok(None);
        }
        let encode = if srgb { srgb8 } else { linear8 };
        let data: Vec<u8> = tex
            .texels
            .iter()
            .flat_map(|p| [encode(p.x), encode(p.y), encode(p.z)])
            .collect();
        if tex.texels.iter().any(|p| p.max_element() > 1.0) {
            self.warnings.push(format!(
                "texture '{}' has texels above 1, clamped to 8-bit [0, 1]",
                tex.name
            ));
        }
        let image = self.png_image(&tex.name, tex.width, tex.height, &data)?;
        let sampler = self.sampler(false);
        self.textures.push(json!({
            "name": tex.name,
            "source": image,
            "sampler": sampler,
        }));
        let t = self.textures.len() - 1;
        self.scene_textures.insert((id, srgb), t);
        Ok(Some(t))
    }

    /// The JSON document.
    pub(super) fn document(&self) -> Value {
        let mut root = Map::new();
        root.insert(
            "asset".into(),
            json!({"version": "2.0", "generator": GENERATOR}),
        );
        if !self.extensions_used.is_empty() {
            root.insert(
                "extensionsUsed".into(),
                json!(self.extensions_used.iter().collect::<Vec<_>>()),
            );
        }
        let node_list: Vec<usize> = (0..self.nodes.len()).collect();
        let mut scene = Map::new();
        if !node_list.is_empty() {
            scene.insert("nodes".into(), json!(node_list));
        }
        root.insert("scene".into(), json!(0));
        root.insert("scenes".into(), json!([scene]));
        for (key, list) in [
            ("nodes", &self.nodes),
            ("meshes", &self.meshes),
            ("cameras", &self.cameras),
            ("materials", &self.materials),
            ("textures", &self.textures),
            ("images", &self.images),
            ("samplers", &self.samplers),
            ("accessors", &self.accessors),
            ("bufferViews", &self.buffer_views),
        ] {
            if !list.is_empty() {
                root.insert(key.into(), Value::Array(list.clone()));
            }
        }
        if !self.bin.is_empty() {
            root.insert("buffers".into(), json!([{"byteLength": self.bin.len()}]));
        }
        if !self.lights.is_empty() {
            root.insert(
                "extensions".into(),
                json!({"KHR_lights_punctual": {"lights": self.lights}}),
            );
        }
        Value::Object(root)
    }

    /// The GLB container: header, JSON chunk (space-padded), BIN chunk
    /// (zero-padded).
    pub(super) fn glb(&mut self) -> Result<Vec<u8>, BakeError> {
        let path = self.path;
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut json_bytes = serde_json::to_vec_pretty(&self.document())
            .map_err(|e| BakeError::file(path, format!("cannot encode the glTF JSON: {e}")))?;
        while !json_bytes.len().is_multiple_of(4) {
            json_bytes.push(b' ');
        }
        let bin_chunk = if self.bin.is_empty() {
            0
        } else {
            8 + self.bin.len()
        };
        let total = 12 + 8 + json_bytes.len() + bin_chunk;
        let total32 = u32::try_from(total).map_err(|_| {
            BakeError::file(
                path,
                format!("the glTF would be {total} bytes, more than a GLB file can hold (4 GiB); lower the atlas size"),
            )
        })?;
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&total32.to_le_bytes());
        out.extend_from_slice(&(json_bytes.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json_bytes);
        if !self.bin.is_empty() {
            out.extend_from_slice(&(self.bin.len() as u32).to_le_bytes());
            out.extend_from_slice(b"BIN\0");
            out.extend_from_slice(&self.bin);
        }
        Ok(out)
    }
}
