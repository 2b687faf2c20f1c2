//! `penumbra study`: renders the truths, then every technique through the
//! same engine calls a user makes from the command line, measures each
//! row against the quantity it approximates and against full GI, and
//! writes the report (all or nothing, see [`crate::output_dir`]).

use crate::error::StudyError;
use crate::measure::errors;
use crate::output_dir::{self, Staging};
use crate::row::{Cost, Errors, Row, Skipped, Study, Truth};
use crate::runner::{Produced, Runner};
use crate::technique::{Technique, TruthKind};
use crate::truth::{Converged, Target, converge};
use penumbra_image::{Image, ToneMapping, ToneOperator, flip_heatmap, read_image, write_image};
use penumbra_scene::{IntegratorKind, RenderSettings, Scene};
use penumbra_trace::geometry::SceneGeometry;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// How to run a study.
#[derive(Clone, Debug)]
pub struct StudyOptions {
    /// The techniques, in report order.
    pub techniques: Vec<Technique>,
    /// The scene's settings with the command line's overrides (resolution,
    /// spp of the ray-traced rows, seed, path depth).
    pub settings: RenderSettings,
    /// A reference EXR to use as the full-GI truth instead of rendering it.
    pub reference: Option<PathBuf>,
    /// When a rendered truth is good enough.
    pub target: Target,
    /// Most seconds each rendered truth may take.
    pub time_budget: Option<f64>,
    /// MSAA samples of the raster rows (1 or 4).
    pub msaa: u32,
    /// The scene file as the user gave it; `None` for the built-in Cornell
    /// box (for the report and the rows' command lines).
    pub scene_file: Option<String>,
}

impl StudyOptions {
    /// The scene's name for people.
    pub fn scene_name(&self) -> String {
        self.scene_file
            .clone()
            .unwrap_or_else(|| "the built-in Cornell box".into())
    }

    /// The scene as a command-line argument (empty for the built-in box).
    pub fn scene_arg(&self) -> String {
        self.scene_file
            .as_ref()
            .map_or(String::new(), |f| format!(" {f}"))
    }
}

/// Called before each stage: (what, stages done, stages in all).
pub type StudyProgress<'a> = &'a dyn Fn(&str, usize, usize);

/// Runs the study of `scene` and writes its report to `dir`.
pub fn run_study(
    scene: &Scene,
    options: &StudyOptions,
    dir: &Path,
    progress: StudyProgress<'_>,
) -> Result<Study, StudyError> {
    let start = Instant::now();
    output_dir::check(dir)?;
    // Refused before any work: neither the truth nor a traced row could
    // render it.
    SceneGeometry::check_size(scene)?;
    if options.techniques.is_empty() {
        return Err(StudyError::Input("no techniques to study".into()));
    }
    let (w, h) = (options.settings.width, options.settings.height);
    let reference = match &options.reference {
        Some(path) => {
            let img = read_image(path)?;
            if (img.width, img.height) != (w, h) {
                return Err(StudyError::Input(format!(
                    "{}: the reference is {}x{} but the study renders {w}x{h} (give --resolution {}x{})",
                    path.display(),
                    img.width,
                    img.height,
                    img.width,
                    img.height
                )));
            }
            Some((path.clone(), img))
        }
        None => None,
    };
    let staging = Staging::new(dir)?;
    let out = staging.path();
    for sub in ["rows", "truths", "bakes"] {
        let p = out.join(sub);
        std::fs::create_dir(&p).map_err(|e| StudyError::file(&p, e))?;
    }

    let mut kinds = vec![TruthKind::Path];
    for t in &options.techniques {
        if !kinds.contains(&t.approximates()) {
            kinds.push(t.approximates());
        }
    }
    let stages = kinds.len() + options.techniques.len();
    let mut stage = 0;
    let mut runner = Runner::new(scene, options, out);

    // The truths.
    let mut truths = Vec::new();
    let mut truth_images: HashMap<TruthKind, Image> = HashMap::new();
    for kind in kinds {
        progress(&format!("truth: {}", kind.id()), stage, stages);
        stage += 1;
        let (image, truth) = match (&reference, kind) {
            (Some((path, img)), TruthKind::Path) => (
                img.clone(),
                Truth {
                    id: kind.id().into(),
                    label: truth_label(kind).into(),
                    source: format!("reference {}", path.display()),
                    image: String::new(),
                    image_exr: String::new(),
                    noise_rel_mse: None,
                    spp: None,
                    seconds: 0.0,
                },
            ),
            _ => {
                let integrator = match kind {
                    TruthKind::Path => IntegratorKind::Path,
                    TruthKind::Direct => IntegratorKind::Direct,
                    TruthKind::Ao => IntegratorKind::Ao,
                };
                let mut base = options.settings.clone();
                base.ao_distance = runner.ao_radius;
                let c = converge(
                    scene,
                    &base,
                    integrator,
                    options.target,
                    options.time_budget,
                )?;
                if kind == TruthKind::Path {
                    runner.path_seconds_per_spp = Some(c.seconds_per_spp());
                }
                let truth = rendered_truth(kind, &c, options, runner.ao_radius);
                (c.image, truth)
            }
        };
        let mut truth = truth;
        truth.image = format!("truths/{}.png", kind.id());
        truth.image_exr = format!("truths/{}.exr", kind.id());
        save(out, &truth.image, &truth.image_exr, &image)?;
        truths.push(truth);
        truth_images.insert(kind, image);
    }
    let full = &truth_images[&TruthKind::Path];

    // The rows.
    let mut rows = Vec::new();
    let mut skipped = Vec::new();
    for technique in &options.techniques {
        let (id, label) = (technique.id(), technique.label());
        progress(&label, stage, stages);
        stage += 1;
        let memory = crate::memory::PeakMemory::start();
        let produced = match runner.run(technique) {
            Ok(p) => p,
            Err(reason) => {
                skipped.push(Skipped { id, label, reason });
                continue;
            }
        };
        let peak_memory_mib = memory.rise_mib();
        let row = finish_row(
            technique,
            produced,
            peak_memory_mib,
            full,
            &truth_images[&technique.approximates()],
            &mut runner,
            out,
        )?;
        rows.push(row);
    }
    progress("report", stage, stages);
    let study = Study {
        scene: options.scene_name(),
        width: w,
        height: h,
        adapter: runner.adapter(),
        version: env!("CARGO_PKG_VERSION").into(),
        truths,
        rows,
        skipped,
        total_seconds: start.elapsed().as_secs_f64(),
    };
    crate::report::write_report(out, &study)?;
    staging.finish(dir)?;
    Ok(study)
}

fn truth_label(kind: TruthKind) -> &'static str {
    match kind {
        TruthKind::Path => "full global illumination (path)",
        TruthKind::Direct => "direct light with exact shadows (direct)",
        TruthKind::Ao => "ray-traced ambient occlusion kA (ao)",
    }
}

fn rendered_truth(kind: TruthKind, c: &Converged, options: &StudyOptions, radius: f32) -> Truth {
    let s = &options.settings;
    let mut source = format!(
        "{} {}x{}, {} spp, max depth {}, seed {}",
        kind.id(),
        s.width,
        s.height,
        c.spp,
        s.max_depth,
        s.seed
    );
    if kind == TruthKind::Ao {
        source += &format!(", AO distance {radius}");
    }
    match options.target {
        Target::RelMse(e) if c.stopped_by_budget => {
            source += &format!(", stopped by the time budget before relMSE {e}")
        }
        Target::RelMse(e) => source += &format!(", target relMSE {e}"),
        Target::Spp(_) if c.stopped_by_budget => source += ", stopped by the time budget",
        Target::Spp(_) => {}
    }
    Truth {
        id: kind.id().into(),
        label: truth_label(kind).into(),
        source,
        image: String::new(),
        image_exr: String::new(),
        noise_rel_mse: Some(c.noise()),
        spp: Some(c.spp),
        seconds: c.seconds,
    }
}

/// Measures a produced row and writes its images.
fn finish_row(
    technique: &Technique,
    produced: Produced,
    peak_memory_mib: Option<f64>,
    full: &Image,
    quantity_truth: &Image,
    runner: &mut Runner<'_>,
    out: &Path,
) -> Result<Row, StudyError> {
    let id = technique.id();
    let (full_errors, flip_map) = errors(full, &produced.image)?;
    let quantity_test = produced.quantity.as_ref().unwrap_or(&produced.image);
    let quantity_errors: Errors = if technique.approximates() == TruthKind::Path {
        full_errors
    } else {
        errors(quantity_truth, quantity_test)?.0
    };
    let image = format!("rows/{id}.png");
    let image_exr = format!("rows/{id}.exr");
    save(out, &image, &image_exr, &produced.image)?;
    let error_map = format!("rows/{id}-error.png");
    let clamp = ToneMapping {
        exposure_ev: 0.0,
        operator: ToneOperator::Clamp,
    };
    write_image(&out.join(&error_map), &flip_heatmap(&flip_map), &[], &clamp)?;
    let quantity_image = match &produced.quantity {
        Some(q) => {
            let png = format!("rows/{id}-quantity.png");
            let exr = format!("rows/{id}-quantity.exr");
            save_with(out, &png, &exr, q, &clamp)?;
            Some(png)
        }
        None => None,
    };
    let equal_time_path = if *technique == Technique::Trace(IntegratorKind::Path) {
        None
    } else {
        runner.path_at_equal_time(produced.seconds, full)?
    };
    Ok(Row {
        id,
        label: technique.label(),
        group: technique.group().into(),
        engine: technique.engine().into(),
        command: produced.command,
        approximates: technique.approximates().id().into(),
        image,
        image_exr,
        error_map,
        quantity_image,
        quantity: quantity_errors,
        full: full_errors,
        equal_time_path,
        cost: Cost {
            bake_seconds: produced.bake_seconds,
            seconds: produced.seconds,
            peak_memory_mib,
        },
        notes: produced.notes,
    })
}

/// Writes `image` as a filmic PNG and a linear EXR.
fn save(out: &Path, png: &str, exr: &str, image: &Image) -> Result<(), StudyError> {
    save_with(out, png, exr, image, &ToneMapping::default())
}

fn save_with(
    out: &Path,
    png: &str,
    exr: &str,
    image: &Image,
    tm: &ToneMapping,
) -> Result<(), StudyError> {
    write_image(&out.join(png), image, &[], tm)?;
    write_image(&out.join(exr), image, &[], tm)?;
    Ok(())
}
