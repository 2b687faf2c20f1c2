//! OpenEXR encoding and decoding (via the `exr` crate).
//!
//! Written files are single-part, scan-line, ZIP16-compressed (lossless),
//! float32, like the Mitsuba references: the beauty image in channels `R, G, B`
//! and each AOV `name` in channels `name.R, name.G, name.B` (the OpenEXR
//! `layer.channel` naming convention), so values round-trip bit-exactly.
//!
//! Reading accepts any part/channel layout: channels are grouped by the prefix
//! before the last `.` (joined with the part's layer name, if any); a group is
//! an RGB image if it has `R`, `G` and `B`, or a grey image if it only has `Y`.
//! F16/F32/U32 samples are converted to f32.

use std::collections::HashSet;
use std::io::Cursor;
use std::path::Path;

use ::exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, LayerAttributes, ReadChannels, ReadLayers,
    Text, WritableImage,
};

use crate::buffer::pixel_count;
use crate::io::{guard, read_file};
use crate::{Image, ImageError, Rgb};

/// Largest pixel count per EXR part accepted when reading (2^28 ≈ 268 M pixels),
/// so a malformed header cannot request an absurd allocation.
pub const MAX_EXR_PIXELS: usize = 1 << 28;

/// All RGB images found in an EXR file.
#[derive(Clone, Debug, PartialEq)]
pub struct ExrLayers {
    /// The beauty image: the unprefixed `R, G, B` channels, or, if the file has
    /// none, the first RGB (or `Y`) channel group.
    pub rgb: Image,
    /// The other channel groups in file order, named by their prefix
    /// (e.g. `"albedo"` for `albedo.R, albedo.G, albedo.B`).
    pub aovs: Vec<(String, Image)>,
}

/// Reads an EXR file's beauty image and all AOV groups (see the module docs).
pub fn read_exr_layers(path: &Path) -> Result<ExrLayers, ImageError> {
    let bytes = read_file(path)?;
    decode(path, &bytes)
}

/// Encodes the beauty image and AOVs as an EXR file in memory.
pub(crate) fn encode(
    path: &Path,
    img: &Image,
    aovs: &[(&str, &Image)],
) -> Result<Vec<u8>, ImageError> {
    let err = |message: String| ImageError::Encode {
        path: path.to_path_buf(),
        format: "EXR",
        message,
    };
    crate::io::check_encodable(img, &err)?;
    let mut channels: Vec<AnyChannel<FlatSamples>> = Vec::with_capacity(3 * (1 + aovs.len()));
    push_rgb(&mut channels, "", img);
    let mut names = HashSet::new();
    for &(name, aov) in aovs {
        if name.is_empty() || name.len() > 250 || !name.bytes().all(|b| (0x21..=0x7e).contains(&b))
        {
            return Err(err(format!(
                "AOV name {name:?} must be 1 to 250 printable ASCII characters without spaces"
            )));
        }
        if !names.insert(name) {
            return Err(err(format!("AOV name {name:?} appears twice")));
        }
        aov.validate(&format!("AOV {name:?}"))
            .map_err(|e| err(e.to_string()))?;
        if (aov.width, aov.height) != (img.width, img.height) {
            return Err(err(format!(
                "AOV {name:?} is {}x{}, image is {}x{}",
                aov.width, aov.height, img.width, img.height
            )));
        }
        push_rgb(&mut channels, &format!("{name}."), aov);
    }

    let attributes = LayerAttributes {
        software_name: Text::new_or_none("penumbra"),
        ..LayerAttributes::default()
    };
    let layer = ::exr::image::Layer::new(
        (img.width as usize, img.height as usize),
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels.into()),
    );
    write_any(&::exr::image::Image::from_layer(layer), &err)
}

/// Encodes an EXR image in memory; `err` wraps a message in the caller's error.
pub(crate) fn write_any<L>(
    image: &::exr::image::Image<L>,
    err: &dyn Fn(String) -> ImageError,
) -> Result<Vec<u8>, ImageError>
where
    L: for<'a> ::exr::image::write::layers::WritableLayers<'a>,
{
    let mut buffer = Vec::new();
    guard(
        || {
            image
                .write()
                .to_buffered(Cursor::new(&mut buffer))
                .map_err(|e| e.to_string())
        },
        err,
    )?;
    Ok(buffer)
}

fn push_rgb(channels: &mut Vec<AnyChannel<FlatSamples>>, prefix: &str, img: &Image) {
    for (c, suffix) in ["R", "G", "B"].into_iter().enumerate() {
        let samples: Vec<f32> = img.pixels.iter().map(|p| p[c]).collect();
        // Names are checked to be printable ASCII above, so this never falls back.
        let name = Text::new_or_none(format!("{prefix}{suffix}")).unwrap_or_default();
        channels.push(AnyChannel::new(name, FlatSamples::F32(samples)));
    }
}

/// One group of channels sharing a prefix: indices of R, G, B, Y in the layer's list.
#[derive(Default)]
struct Group {
    name: String,
    rgby: [Option<usize>; 4],
}

/// An EXR file as the `exr` crate reads it: every part, channel and attribute.
pub(crate) type AnyExr = ::exr::image::Image<::exr::image::Layers<AnyChannels<FlatSamples>>>;

/// Reads every part, channel and attribute of an EXR file held in memory,
/// after checking the header, so absurd sizes are refused before allocating;
/// `err` wraps a message in the caller's error.
pub(crate) fn read_any(
    bytes: &[u8],
    err: &dyn Fn(String) -> ImageError,
) -> Result<AnyExr, ImageError> {
    let meta = guard(
        || {
            ::exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), true)
                .map_err(|e| e.to_string())
        },
        err,
    )?;
    for header in meta.headers.iter() {
        let (w, h) = (header.layer_size.0, header.layer_size.1);
        if w.checked_mul(h).is_none_or(|n| n > MAX_EXR_PIXELS) {
            return Err(err(format!("image size {w}x{h} is too large")));
        }
    }
    guard(
        || {
            ::exr::prelude::read()
                .no_deep_data()
                .largest_resolution_level()
                .all_channels()
                .all_layers()
                .all_attributes()
                .pedantic()
                .from_buffered(Cursor::new(bytes))
                .map_err(|e| e.to_string())
        },
        err,
    )
}

/// Decodes an EXR file held in memory.
pub(crate) fn decode(path: &Path, bytes: &[u8]) -> Result<ExrLayers, ImageError> {
    let err = |message: String| ImageError::Decode {
        path: path.to_path_buf(),
        format: "EXR",
        message,
    };

    let image = read_any(bytes, &err)?;

    let mut found: Vec<(String, Image)> = Vec::new();
    let mut all_names: Vec<String> = Vec::new();
    for layer in image.layer_data.iter() {
        let part = layer
            .attributes
            .layer_name
            .as_ref()
            .map(|t| t.to_string())
            .unwrap_or_default();
        let (w, h) = (layer.size.0, layer.size.1);
        let (Ok(width), Ok(height)) = (u32::try_from(w), u32::try_from(h)) else {
            return Err(err(format!("image size {w}x{h} is too large")));
        };
        let list = &layer.channel_data.list;
        let mut groups: Vec<Group> = Vec::new();
        for (i, channel) in list.iter().enumerate() {
            let full = channel.name.to_string();
            all_names.push(if part.is_empty() {
                full.clone()
            } else {
                format!("{part}/{full}")
            });
            let (prefix, suffix) = match full.rfind('.') {
                Some(p) => (&full[..p], &full[p + 1..]),
                None => ("", full.as_str()),
            };
            let slot = match suffix {
                "R" => 0,
                "G" => 1,
                "B" => 2,
                "Y" => 3,
                _ => continue,
            };
            let name = match (part.is_empty(), prefix.is_empty()) {
                (_, true) => part.clone(),
                (true, false) => prefix.to_string(),
                (false, false) => format!("{part}.{prefix}"),
            };
            let index = match groups.iter().position(|g| g.name == name) {
                Some(index) => index,
                None => {
                    groups.push(Group {
                        name,
                        ..Group::default()
                    });
                    groups.len() - 1
                }
            };
            groups[index].rgby[slot] = Some(i);
        }
        for group in groups {
            let sources = match group.rgby {
                [Some(r), Some(g), Some(b), _] => [r, g, b],
                [None, None, None, Some(y)] => [y, y, y],
                _ => continue,
            };
            let n = pixel_count(width, height);
            let mut pixels = vec![Rgb::ZERO; n];
            for (c, &source) in sources.iter().enumerate() {
                let samples = &list[source].sample_data;
                if samples.len() != n {
                    return Err(err(format!(
                        "channel {} has {} samples for a {width}x{height} image (subsampled channels are not supported)",
                        list[source].name,
                        samples.len()
                    )));
                }
                for (p, v) in pixels.iter_mut().zip(samples.values_as_f32()) {
                    p[c] = v;
                }
            }
            found.push((
                group.name,
                Image {
                    width,
                    height,
                    pixels,
                },
            ));
        }
    }

    let beauty = found
        .iter()
        .position(|(name, _)| name.is_empty())
        .or(if found.is_empty() { None } else { Some(0) });
    let Some(beauty) = beauty else {
        return Err(err(format!(
            "no R,G,B (or Y) channels found; channels: [{}]",
            all_names.join(", ")
        )));
    };
    let (_, rgb) = found.remove(beauty);
    Ok(ExrLayers { rgb, aovs: found })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encode_rejects_bad_aovs() {
        let p = Path::new("x.exr");
        let img = Image::new(2, 2);
        let small = Image::new(1, 2);
        assert!(encode(p, &img, &[("albedo", &small)]).is_err());
        assert!(encode(p, &img, &[("", &img)]).is_err());
        assert!(encode(p, &img, &[("a b", &img)]).is_err());
        assert!(encode(p, &img, &[("n", &img), ("n", &img)]).is_err());
        assert!(encode(p, &Image::new(0, 0), &[]).is_err());
        let broken = Image {
            width: 2,
            height: 2,
            pixels: vec![],
        };
        assert!(encode(p, &broken, &[]).is_err());
    }

    #[test]
    fn decode_in_memory_round_trip() {
        let p = Path::new("mem.exr");
        let img = Image::from_fn(3, 2, |x, y| Rgb::new(x as f32, y as f32, -0.5));
        let bytes = encode(p, &img, &[]).expect("encode");
        let layers = decode(p, &bytes).expect("decode");
        assert_eq!(layers.rgb, img);
        assert!(layers.aovs.is_empty());
    }
}
