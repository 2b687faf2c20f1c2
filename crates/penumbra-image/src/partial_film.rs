//! [`PartialFilm`]: the sample sums of part of a render (a range of sample
//! indices over a window of the image), stored as an EXR file so that parts
//! rendered on different machines, or a checkpoint of an unfinished render,
//! can be added into the image later.
//!
//! # File format (version 1)
//! A single-part, scan-line, ZIP-compressed OpenEXR file whose display
//! window is the whole image and whose data window is the part's window:
//! - `R, G, B` (f32): the mean `Σv / n`, so that any EXR viewer shows the part;
//! - `film.count` (u32): the sample count `n` of each pixel;
//! - `film.sum.{R,G,B}.w0 … w3` (u32): the exact sum `Σv` as a two's-complement
//!   128-bit integer in units of 2⁻⁴⁸ ([`crate::film`]), least significant word first;
//! - `film.sumsq.{R,G,B}.lo, .hi` (u32): the bits of the f64 sum of squares `Σv²`;
//! - attributes `penumbra.film` = `"1"`, `penumbra.samples` = `"A..B"` (sample
//!   indices held by every pixel of the window), `penumbra.spp` (the complete
//!   render's samples per pixel), `penumbra.rejected` (samples not accumulated)
//!   and `penumbra.render`: one `key=value` line per setting that must be
//!   equal in all parts of a render (the scene's fingerprint, the integrator,
//!   the seed, …).

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use ::exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, ImageAttributes, IntegerBounds,
    LayerAttributes, Text, Vec2,
};
use glam::DVec3;

use crate::buffer::pixel_count;
use crate::exr_io::{read_any, write_any};
use crate::film::PixelStats;
use crate::io::{check_output_path, read_file, write_atomic};
use crate::{Film, ImageError};

/// The version written in `penumbra.film`.
const FORMAT_VERSION: &str = "1";

/// Sample sums of sample indices `samples` over the window of `film`.
#[derive(Clone, Debug, PartialEq)]
pub struct PartialFilm {
    /// Width of the whole image.
    pub image_width: u32,
    /// Height of the whole image.
    pub image_height: u32,
    /// The sample indices every pixel of the window holds (a pixel may hold
    /// fewer samples where some were rejected).
    pub samples: Range<u32>,
    /// Samples per pixel of the complete render.
    pub spp: u32,
    /// Settings that must be equal in every part of one render, by name.
    pub identity: BTreeMap<String, String>,
    /// The sums, over the part's window (absolute pixel coordinates).
    pub film: Film,
}

impl PartialFilm {
    /// Whether this part holds every sample of every pixel of the render.
    pub fn is_complete(&self) -> bool {
        self.samples == (0..self.spp)
            && (self.film.x0(), self.film.y0()) == (0, 0)
            && (self.film.width(), self.film.height()) == (self.image_width, self.image_height)
    }

    /// The part's extent in words: `pixels x0..x1 × y0..y1, samples a..b`.
    pub fn extent(&self) -> String {
        let (xs, ys) = self.window();
        describe_cell((self.image_width, self.image_height), xs, ys, &self.samples)
    }

    /// The pixel columns and rows of the part's window.
    pub fn window(&self) -> (Range<u32>, Range<u32>) {
        let f = &self.film;
        (f.x0()..f.x0() + f.width(), f.y0()..f.y0() + f.height())
    }

    /// What every part of one render shares, by name (see [`render_key`]).
    pub fn render_key(&self) -> BTreeMap<String, String> {
        render_key(
            (self.image_width, self.image_height),
            self.spp,
            &self.identity,
        )
    }
}

/// What every part of one render shares, by name: `image` (`WxH`), `spp`
/// (of the whole render) and the identity settings.
pub fn render_key(
    (width, height): (u32, u32),
    spp: u32,
    identity: &BTreeMap<String, String>,
) -> BTreeMap<String, String> {
    let mut key = identity.clone();
    key.insert("image".into(), format!("{width}x{height}"));
    key.insert("spp".into(), spp.to_string());
    key
}

/// The entries where two render keys differ: (name, value in `a`, value in
/// `b`), "nothing" where one lacks the name.
pub fn key_differences(
    a: &BTreeMap<String, String>,
    b: &BTreeMap<String, String>,
) -> Vec<(String, String, String)> {
    let value = |m: &BTreeMap<String, String>, k: &String| {
        m.get(k).cloned().unwrap_or_else(|| "nothing".into())
    };
    let names: std::collections::BTreeSet<&String> = a.keys().chain(b.keys()).collect();
    names
        .into_iter()
        .filter(|k| a.get(*k) != b.get(*k))
        .map(|k| (k.clone(), value(a, k), value(b, k)))
        .collect()
}

fn describe_cell(
    (width, height): (u32, u32),
    xs: Range<u32>,
    ys: Range<u32>,
    samples: &Range<u32>,
) -> String {
    let pixels = if xs == (0..width) && ys == (0..height) {
        "every pixel".to_string()
    } else {
        format!(
            "pixels x {}..{} × y {}..{}",
            xs.start, xs.end, ys.start, ys.end
        )
    };
    format!("samples {}..{} of {pixels}", samples.start, samples.end)
}

/// Writes `part` to `path` (`.exr`) atomically (see the module docs).
pub fn write_partial_film(path: &Path, part: &PartialFilm) -> Result<(), ImageError> {
    check_output_path(path)?;
    let bytes = encode(path, part)?;
    write_atomic(path, &bytes)
}

/// Reads a partial film written by [`write_partial_film`]; any other file
/// (an ordinary EXR image, a damaged or inconsistent part) is an error
/// naming the file and what is wrong.
pub fn read_partial_film(path: &Path) -> Result<PartialFilm, ImageError> {
    let bytes = read_file(path)?;
    decode(path, &bytes)
}

fn encode(path: &Path, part: &PartialFilm) -> Result<Vec<u8>, ImageError> {
    let err = |message: String| ImageError::Encode {
        path: path.to_path_buf(),
        format: "EXR partial film",
        message,
    };
    let film = &part.film;
    if film.width() == 0 || film.height() == 0 {
        return Err(err("the film's window is empty".into()));
    }
    let stats = film.stats();
    let mut channels: Vec<AnyChannel<FlatSamples>> = Vec::new();
    let mut push = |name: String, samples: FlatSamples| {
        channels.push(AnyChannel::new(
            Text::new_or_none(name).unwrap_or_default(),
            samples,
        ));
    };
    let mean = film.mean();
    for (c, ch) in ["R", "G", "B"].into_iter().enumerate() {
        push(
            ch.to_string(),
            FlatSamples::F32(mean.pixels.iter().map(|p| p[c]).collect()),
        );
        for w in 0..4 {
            let words = stats.iter().map(|s| (s.sum[c] as u128 >> (32 * w)) as u32);
            push(
                format!("film.sum.{ch}.w{w}"),
                FlatSamples::U32(words.collect()),
            );
        }
        let bits = |s: &PixelStats| s.sum_sq[c].to_bits();
        push(
            format!("film.sumsq.{ch}.lo"),
            FlatSamples::U32(stats.iter().map(|s| bits(s) as u32).collect()),
        );
        push(
            format!("film.sumsq.{ch}.hi"),
            FlatSamples::U32(stats.iter().map(|s| (bits(s) >> 32) as u32).collect()),
        );
    }
    push(
        "film.count".to_string(),
        FlatSamples::U32(stats.iter().map(|s| s.n).collect()),
    );

    let text = |s: &str| AttributeValue::Text(Text::new_or_none(s).unwrap_or_default());
    let mut attributes = LayerAttributes {
        software_name: Text::new_or_none("penumbra"),
        layer_position: Vec2(film.x0() as i32, film.y0() as i32),
        ..LayerAttributes::default()
    };
    let identity: String = part
        .identity
        .iter()
        .map(|(k, v)| format!("{k}={v}\n"))
        .collect();
    for (name, value) in [
        ("penumbra.film", FORMAT_VERSION.to_string()),
        (
            "penumbra.samples",
            format!("{}..{}", part.samples.start, part.samples.end),
        ),
        ("penumbra.spp", part.spp.to_string()),
        ("penumbra.rejected", film.rejected_samples().to_string()),
        ("penumbra.render", identity),
    ] {
        attributes
            .other
            .insert(Text::new_or_panic(name), text(&value));
    }
    let layer = ::exr::image::Layer::new(
        (film.width() as usize, film.height() as usize),
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels.into()),
    );
    let display =
        IntegerBounds::from_dimensions((part.image_width as usize, part.image_height as usize));
    write_any(
        &::exr::image::Image::new(ImageAttributes::new(display), layer),
        &err,
    )
}

fn decode(path: &Path, bytes: &[u8]) -> Result<PartialFilm, ImageError> {
    let err = |message: String| ImageError::Decode {
        path: path.to_path_buf(),
        format: "EXR partial film",
        message,
    };
    let image = read_any(bytes, &err)?;
    let [layer] = image.layer_data.as_slice() else {
        return Err(err(format!(
            "a partial film has one part, this file has {}",
            image.layer_data.len()
        )));
    };
    let attribute = |name: &str| -> Result<String, ImageError> {
        match layer.attributes.other.get(&Text::new_or_panic(name)) {
            Some(AttributeValue::Text(t)) => Ok(t.to_string()),
            Some(_) => Err(err(format!("attribute {name} is not text"))),
            None => Err(err(format!(
                "no attribute {name}: not a partial film (penumbra render --samples/--crop or --checkpoint writes one)"
            ))),
        }
    };
    let version = attribute("penumbra.film")?;
    if version != FORMAT_VERSION {
        return Err(err(format!(
            "partial-film format {version} is not supported (this penumbra reads {FORMAT_VERSION})"
        )));
    }
    let number = |name: &str| -> Result<u64, ImageError> {
        let text = attribute(name)?;
        text.trim()
            .parse()
            .map_err(|_| err(format!("attribute {name} = {text:?} is not a number")))
    };
    let spp = u32::try_from(number("penumbra.spp")?)
        .map_err(|_| err("attribute penumbra.spp is too large".into()))?;
    let rejected = number("penumbra.rejected")?;
    let samples_text = attribute("penumbra.samples")?;
    let samples = parse_range(&samples_text)
        .filter(|r| r.end <= spp)
        .ok_or_else(|| {
            err(format!(
                "attribute penumbra.samples = {samples_text:?} is not a range A..B within 0..{spp}"
            ))
        })?;
    let mut identity = BTreeMap::new();
    for line in attribute("penumbra.render")?.lines() {
        let Some((k, v)) = line.split_once('=') else {
            return Err(err(format!(
                "attribute penumbra.render: line {line:?} is not key=value"
            )));
        };
        identity.insert(k.to_string(), v.to_string());
    }

    let display = image.attributes.display_window;
    let position = layer.attributes.layer_position;
    let (width, height) = (layer.size.0, layer.size.1);
    let (Ok(x0), Ok(y0), Ok(w), Ok(h), Ok(iw), Ok(ih)) = (
        u32::try_from(position.0),
        u32::try_from(position.1),
        u32::try_from(width),
        u32::try_from(height),
        u32::try_from(display.size.0),
        u32::try_from(display.size.1),
    ) else {
        return Err(err("window or image size out of range".into()));
    };
    if display.position != Vec2(0, 0)
        || x0.checked_add(w).is_none_or(|x1| x1 > iw)
        || y0.checked_add(h).is_none_or(|y1| y1 > ih)
    {
        return Err(err(format!(
            "window {x0},{y0} size {w}x{h} does not lie inside the {iw}x{ih} image"
        )));
    }

    let n = pixel_count(w, h);
    let channel = |name: &str| -> Result<&Vec<u32>, ImageError> {
        let found = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
            .ok_or_else(|| err(format!("channel {name} is missing")))?;
        match &found.sample_data {
            FlatSamples::U32(v) if v.len() == n => Ok(v),
            _ => Err(err(format!("channel {name} is not {n} u32 samples"))),
        }
    };
    let mut stats = vec![PixelStats::default(); n];
    for (s, &count) in stats.iter_mut().zip(channel("film.count")?) {
        s.n = count;
    }
    for (c, ch) in ["R", "G", "B"].into_iter().enumerate() {
        for w in 0..4 {
            let words = channel(&format!("film.sum.{ch}.w{w}"))?;
            for (s, &word) in stats.iter_mut().zip(words) {
                s.sum[c] = (s.sum[c] as u128 | (u128::from(word) << (32 * w))) as i128;
            }
        }
        let lo = channel(&format!("film.sumsq.{ch}.lo"))?;
        let hi = channel(&format!("film.sumsq.{ch}.hi"))?;
        for ((s, &lo), &hi) in stats.iter_mut().zip(lo).zip(hi) {
            let mut v = s.sum_sq.to_array();
            v[c] = f64::from_bits(u64::from(lo) | (u64::from(hi) << 32));
            s.sum_sq = DVec3::from_array(v);
        }
    }
    if let Some(bad) = stats
        .iter()
        .position(|s| s.n > samples.len() as u32 || !s.sum_sq.is_finite())
    {
        return Err(err(format!(
            "pixel {} holds {} samples, more than its range {}..{}, or a broken sum",
            bad, stats[bad].n, samples.start, samples.end
        )));
    }
    let film = Film::from_stats((x0, y0, w, h), stats, rejected)
        .ok_or_else(|| err("channel sizes do not match the window".into()))?;
    Ok(PartialFilm {
        image_width: iw,
        image_height: ih,
        samples,
        spp,
        identity,
        film,
    })
}

/// Parses `A..B` (A ≤ B).
pub fn parse_range(s: &str) -> Option<Range<u32>> {
    let (a, b) = s.trim().split_once("..")?;
    let (a, b) = (a.trim().parse().ok()?, b.trim().parse().ok()?);
    (a <= b).then_some(a..b)
}

/// Most cells of the hole search in [`merge_parts`] before it only reports
/// the number of missing samples.
const MAX_HOLE_CELLS: usize = 1 << 20;

/// Adds the parts of one render into the complete film, after checking that
/// they belong to the same render (image size, samples per pixel and every
/// identity setting equal), that no two hold the same sample of a pixel, and
/// that together they hold every sample of every pixel. Errors name the odd
/// part, the overlapping pair, or the missing samples. The sums add exactly,
/// so the result does not depend on the order of `parts`.
pub fn merge_parts(parts: &[(PathBuf, PartialFilm)]) -> Result<PartialFilm, ImageError> {
    let merge_err = |message: String| ImageError::Merge { message };
    let Some((_, first)) = parts.first() else {
        return Err(merge_err("no parts to merge".into()));
    };
    // The key most parts share is the render's; name every other part.
    let keys: Vec<BTreeMap<String, String>> = parts.iter().map(|(_, p)| p.render_key()).collect();
    let mut counts: BTreeMap<&BTreeMap<String, String>, usize> = BTreeMap::new();
    for k in &keys {
        *counts.entry(k).or_default() += 1;
    }
    if counts.len() > 1 {
        let main = counts
            .iter()
            .max_by_key(|(_, n)| **n)
            .map(|(k, _)| (*k).clone())
            .unwrap_or_default();
        let lines: Vec<String> = parts
            .iter()
            .zip(&keys)
            .filter(|(_, k)| **k != main)
            .map(|((path, _), k)| {
                let d = key_differences(k, &main);
                let side = |pick: fn(&(String, String, String)) -> String| {
                    d.iter().map(pick).collect::<Vec<_>>().join(", ")
                };
                format!(
                    "{}: belongs to another render: {} (the other parts have {})",
                    path.display(),
                    side(|(n, v, _)| format!("{n} = {v}")),
                    side(|(n, _, v)| format!("{n} = {v}"))
                )
            })
            .collect();
        return Err(merge_err(lines.join("\n")));
    }

    let boxes: Vec<[Range<u32>; 3]> = parts
        .iter()
        .map(|(_, p)| {
            let (xs, ys) = p.window();
            [xs, ys, p.samples.clone()]
        })
        .collect();
    let overlap = |a: &Range<u32>, b: &Range<u32>| a.start.max(b.start)..a.end.min(b.end);
    for i in 0..boxes.len() {
        for j in i + 1..boxes.len() {
            let o: Vec<Range<u32>> = (0..3)
                .map(|k| overlap(&boxes[i][k], &boxes[j][k]))
                .collect();
            if o.iter().all(|r| !r.is_empty()) {
                return Err(merge_err(format!(
                    "{} and {} both hold {}",
                    parts[i].0.display(),
                    parts[j].0.display(),
                    describe_cell(
                        (first.image_width, first.image_height),
                        o[0].clone(),
                        o[1].clone(),
                        &o[2]
                    )
                )));
            }
        }
    }

    let (w, h, spp) = (first.image_width, first.image_height, first.spp);
    let volume = |b: &[Range<u32>; 3]| b.iter().map(|r| r.len() as u128).product::<u128>();
    let held: u128 = boxes.iter().map(volume).sum();
    let wanted = u128::from(w) * u128::from(h) * u128::from(spp);
    if held < wanted {
        return Err(merge_err(missing_samples(
            &boxes,
            (w, h, spp),
            wanted - held,
        )));
    }

    let mut film = Film::new(w, h);
    for (_, p) in parts {
        film.merge(&p.film);
    }
    Ok(PartialFilm {
        image_width: w,
        image_height: h,
        samples: 0..spp,
        spp,
        identity: first.identity.clone(),
        film,
    })
}

/// Names the (pixel window × sample range) cells no part holds: the grid cut
/// by every part's edges, each cell either wholly held by one part or by none.
fn missing_samples(
    boxes: &[[Range<u32>; 3]],
    (w, h, spp): (u32, u32, u32),
    missing: u128,
) -> String {
    let cuts = |k: usize, end: u32| {
        let mut c: Vec<u32> = boxes.iter().flat_map(|b| [b[k].start, b[k].end]).collect();
        c.extend([0, end]);
        c.sort_unstable();
        c.dedup();
        c
    };
    let (xs, ys, ss) = (cuts(0, w), cuts(1, h), cuts(2, spp));
    let mut holes = Vec::new();
    let cells = (xs.len() - 1) * (ys.len() - 1) * (ss.len() - 1);
    if cells <= MAX_HOLE_CELLS {
        'search: for s in ss.windows(2) {
            for y in ys.windows(2) {
                for x in xs.windows(2) {
                    let held = boxes.iter().any(|b| {
                        b[0].contains(&x[0]) && b[1].contains(&y[0]) && b[2].contains(&s[0])
                    });
                    if !held {
                        holes.push(describe_cell((w, h), x[0]..x[1], y[0]..y[1], &(s[0]..s[1])));
                        if holes.len() == 8 {
                            break 'search;
                        }
                    }
                }
            }
        }
    }
    format!(
        "the parts miss {missing} pixel samples of the {w}x{h} image at {spp} spp{}{}",
        if holes.is_empty() { "" } else { ": " },
        holes.join("; ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Rgb;

    /// The value of sample `s` of pixel (x, y): any deterministic function.
    fn value(x: u32, y: u32, s: u32) -> Rgb {
        let h =
            (x.wrapping_mul(73_856_093) ^ y.wrapping_mul(19_349_663) ^ s.wrapping_mul(83_492_791))
                % 10_007;
        Rgb::new(
            h as f32 * 1e-3,
            (h % 97) as f32 * 1e3,
            1.0 / (1.0 + h as f32),
        )
    }

    fn part(x: Range<u32>, y: Range<u32>, samples: Range<u32>, seed: &str) -> PartialFilm {
        let mut film = Film::window(x.start, y.start, x.len() as u32, y.len() as u32);
        for s in samples.clone() {
            for py in y.clone() {
                for px in x.clone() {
                    film.add_sample(px, py, value(px, py, s));
                }
            }
        }
        PartialFilm {
            image_width: 6,
            image_height: 4,
            samples,
            spp: 12,
            identity: BTreeMap::from([
                ("scene".to_string(), "fnv1a64:0123".to_string()),
                ("seed".to_string(), seed.to_string()),
            ]),
            film,
        }
    }

    fn named(parts: Vec<PartialFilm>) -> Vec<(PathBuf, PartialFilm)> {
        parts
            .into_iter()
            .enumerate()
            .map(|(i, p)| (PathBuf::from(format!("part{i}.exr")), p))
            .collect()
    }

    #[test]
    fn file_round_trip_is_exact() {
        let p = part(1..5, 2..4, 3..9, "7");
        let bytes = encode(Path::new("p.exr"), &p).unwrap();
        let back = decode(Path::new("p.exr"), &bytes).unwrap();
        assert_eq!(back, p);
        assert_eq!(back.extent(), "samples 3..9 of pixels x 1..5 × y 2..4");
        // An ordinary EXR image is not a partial film.
        let plain = crate::exr_io::encode(Path::new("i.exr"), &p.film.mean(), &[]).unwrap();
        let e = decode(Path::new("i.exr"), &plain).unwrap_err().to_string();
        assert!(
            e.contains("i.exr") && e.contains("not a partial film"),
            "{e}"
        );
    }

    #[test]
    fn ranges_and_windows_merge_to_the_whole_in_any_order() {
        let whole = part(0..6, 0..4, 0..12, "7");
        let by_samples = vec![
            part(0..6, 0..4, 5..9, "7"),
            part(0..6, 0..4, 0..1, "7"),
            part(0..6, 0..4, 9..12, "7"),
            part(0..6, 0..4, 1..5, "7"),
        ];
        let mut reversed = by_samples.clone();
        reversed.reverse();
        for parts in [by_samples, reversed] {
            let merged = merge_parts(&named(parts)).unwrap();
            assert!(merged.is_complete());
            assert_eq!(merged.film.mean(), whole.film.mean());
        }
        // Two crops plus the rest (an L-shaped remainder in two windows).
        let crops = vec![
            part(0..3, 0..2, 0..12, "7"),
            part(3..6, 0..2, 0..12, "7"),
            part(0..6, 2..4, 0..6, "7"),
            part(0..6, 2..4, 6..12, "7"),
        ];
        let merged = merge_parts(&named(crops)).unwrap();
        assert_eq!(merged.film.mean(), whole.film.mean());
    }

    #[test]
    fn overlaps_holes_and_strangers_are_named() {
        let e = merge_parts(&named(vec![
            part(0..6, 0..4, 0..7, "7"),
            part(0..6, 0..4, 6..12, "7"),
        ]))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("part0.exr and part1.exr both hold samples 6..7 of every pixel"),
            "{e}"
        );
        let e = merge_parts(&named(vec![
            part(0..6, 0..4, 0..4, "7"),
            part(0..6, 0..4, 8..12, "7"),
        ]))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("miss 96 pixel samples") && e.contains("samples 4..8 of every pixel"),
            "{e}"
        );
        let e = merge_parts(&named(vec![
            part(0..6, 0..4, 0..12, "7"),
            part(2..3, 1..2, 0..0, "7"),
        ]));
        assert!(
            e.is_ok(),
            "an empty range holds nothing and overlaps nothing"
        );
        let e = merge_parts(&named(vec![
            part(0..6, 0..2, 0..12, "7"),
            part(0..3, 2..4, 0..12, "7"),
        ]))
        .unwrap_err()
        .to_string();
        assert!(e.contains("samples 0..12 of pixels x 3..6 × y 2..4"), "{e}");
        let e = merge_parts(&named(vec![
            part(0..6, 0..4, 0..4, "7"),
            part(0..6, 0..4, 4..8, "8"),
            part(0..6, 0..4, 8..12, "7"),
        ]))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains(
                "part1.exr: belongs to another render: seed = 8 (the other parts have seed = 7)"
            ),
            "{e}"
        );
        let mut other_spp = part(0..6, 0..4, 4..8, "7");
        other_spp.spp = 16;
        let e = merge_parts(&named(vec![
            part(0..6, 0..4, 0..4, "7"),
            other_spp,
            part(0..6, 0..4, 8..12, "7"),
        ]))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("part1.exr") && e.contains("spp = 16") && e.contains("spp = 12"),
            "{e}"
        );
    }
}
