//! Where a path sample's time goes, stage by stage: with the
//! `stage-timing` feature, [`timed`] reads the CPU's time-stamp counter
//! around each stage of the render loop and the path tracer (the closest
//! hit, its BVH traversal, shading, next-event estimation, its shadow ray,
//! BSDF sampling) and counts the calls; `penumbra bench` prints the split
//! after its path measure (`scripts/stage-times.sh`). It also counts what
//! the single-ray closest-hit walk visits ([`visited`]: nodes, leaves and
//! the leaves' triangles), which `bench` prints per query. Without the
//! feature [`timed`] is the bare call and nothing is counted.
//!
//! It exists because these machines expose no performance counters, and
//! instruction counts (`scripts/instructions-per-sample.sh`) do not price
//! latency or mispredicted branches. A stage's time is inclusive: the
//! shadow ray is inside next-event estimation, the traversal inside the
//! closest hit, and everything inside the sample. Reading the counter
//! costs some 20–40 cycles, and it does not wait for earlier work to
//! finish, so stages of a few dozen cycles are measured coarsely; the
//! instrumented build ran about 5 % slower on the Cornell box.

/// A stage of the render loop or the path tracer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// One camera sample: its camera ray and path (not the film's sum).
    Sample,
    /// A closest-hit query of the path tracer: traversal and the
    /// `SurfaceHit` built from its hit.
    Closest,
    /// The BVH traversal of a closest-hit query.
    Traversal,
    /// Next-event estimation at a path vertex, shadow ray included.
    NextEvent,
    /// The shadow ray of next-event estimation.
    Shadow,
    /// The BSDF at a hit (`TraceContext::shading`).
    Shading,
    /// BSDF sampling of the next segment (`path::scatter`).
    Scatter,
}

impl Stage {
    pub const ALL: [Stage; 7] = [
        Stage::Sample,
        Stage::Closest,
        Stage::Traversal,
        Stage::NextEvent,
        Stage::Shadow,
        Stage::Shading,
        Stage::Scatter,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Stage::Sample => "sample",
            Stage::Closest => "closest-hit",
            Stage::Traversal => "traversal",
            Stage::NextEvent => "next-event",
            Stage::Shadow => "shadow-ray",
            Stage::Shading => "shading",
            Stage::Scatter => "scatter",
        }
    }

    /// The stage this one runs inside, below the sample (whose time holds
    /// every other stage's).
    pub fn within(self) -> Option<Stage> {
        match self {
            Stage::Traversal => Some(Stage::Closest),
            Stage::Shadow => Some(Stage::NextEvent),
            _ => None,
        }
    }
}

/// One stage's total over the samples since the last [`take`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StageTime {
    pub stage: Stage,
    /// Time-stamp counter ticks (x86-64; nanoseconds elsewhere).
    pub ticks: u64,
    pub calls: u64,
}

/// Whether this build times its stages (the `stage-timing` feature).
pub const ENABLED: bool = cfg!(feature = "stage-timing");

/// `f()`, timed as `stage` when [`ENABLED`].
#[inline(always)]
pub fn timed<T>(stage: Stage, f: impl FnOnce() -> T) -> T {
    #[cfg(feature = "stage-timing")]
    {
        let t0 = counter::now();
        let out = f();
        counter::add(stage, counter::now().wrapping_sub(t0));
        out
    }
    #[cfg(not(feature = "stage-timing"))]
    {
        let _ = stage;
        f()
    }
}

/// Adds this thread's counts to the totals [`take`] returns (the render
/// loop calls it after each tile).
#[inline]
pub fn flush() {
    #[cfg(feature = "stage-timing")]
    counter::flush();
}

/// The totals since the last call (every thread's flushed counts), in
/// [`Stage::ALL`]'s order; `None` when not [`ENABLED`].
pub fn take() -> Option<Vec<StageTime>> {
    #[cfg(feature = "stage-timing")]
    {
        Some(counter::take())
    }
    #[cfg(not(feature = "stage-timing"))]
    {
        None
    }
}

/// What the single-ray closest-hit walk visits (`accel::traverse::Walk`;
/// the packet walks' own node tests are not counted, their rays' single-ray
/// parts are).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Visit {
    /// An inner node: one 8-wide box test.
    Node,
    /// A leaf: one triangle test of its one or two blocks.
    Leaf,
    /// The triangles of the visited leaves.
    Triangles,
}

impl Visit {
    /// Every kind, in counter order.
    pub const ALL: [Visit; 3] = [Visit::Node, Visit::Leaf, Visit::Triangles];
}

/// Node visits, leaf visits and the leaves' triangles, summed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Visits {
    pub nodes: u64,
    pub leaves: u64,
    pub triangles: u64,
}

/// Counts `n` of `what` when [`ENABLED`].
#[inline(always)]
pub fn visited(what: Visit, n: u64) {
    #[cfg(feature = "stage-timing")]
    counter::visit(what, n);
    #[cfg(not(feature = "stage-timing"))]
    let _ = (what, n);
}

/// The visits since the last call (every thread's flushed counts); `None`
/// when not [`ENABLED`].
pub fn take_visits() -> Option<Visits> {
    #[cfg(feature = "stage-timing")]
    {
        Some(counter::take_visits())
    }
    #[cfg(not(feature = "stage-timing"))]
    {
        None
    }
}

#[cfg(feature = "stage-timing")]
#[allow(unsafe_code)]
mod counter {
    use super::{Stage, StageTime, Visit, Visits};
    use std::cell::Cell;
    use std::sync::atomic::{AtomicU64, Ordering};

    const N: usize = Stage::ALL.len();
    const KINDS: usize = Visit::ALL.len();

    thread_local! {
        static LOCAL: [Cell<(u64, u64)>; N] = const { [const { Cell::new((0, 0)) }; N] };
        static LOCAL_VISITS: [Cell<u64>; KINDS] = const { [const { Cell::new(0) }; KINDS] };
    }
    static TICKS: [AtomicU64; N] = [const { AtomicU64::new(0) }; N];
    static CALLS: [AtomicU64; N] = [const { AtomicU64::new(0) }; N];
    static VISITS: [AtomicU64; KINDS] = [const { AtomicU64::new(0) }; KINDS];

    #[inline(always)]
    pub fn visit(what: Visit, n: u64) {
        LOCAL_VISITS.with(|l| {
            let c = &l[what as usize];
            c.set(c.get() + n);
        });
    }

    /// This thread's visits not yet flushed.
    #[cfg(test)]
    pub fn local_visits() -> Visits {
        LOCAL_VISITS.with(|l| Visits {
            nodes: l[Visit::Node as usize].get(),
            leaves: l[Visit::Leaf as usize].get(),
            triangles: l[Visit::Triangles as usize].get(),
        })
    }

    pub fn take_visits() -> Visits {
        let take = |v: Visit| VISITS[v as usize].swap(0, Ordering::Relaxed);
        Visits {
            nodes: take(Visit::Node),
            leaves: take(Visit::Leaf),
            triangles: take(Visit::Triangles),
        }
    }

    #[inline(always)]
    pub fn now() -> u64 {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: RDTSC is part of x86-64 and has no preconditions.
            unsafe { std::arch::x86_64::_rdtsc() }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            use std::sync::OnceLock;
            static START: OnceLock<std::time::Instant> = OnceLock::new();
            START
                .get_or_init(std::time::Instant::now)
                .elapsed()
                .as_nanos() as u64
        }
    }

    #[inline(always)]
    pub fn add(stage: Stage, ticks: u64) {
        LOCAL.with(|l| {
            let c = &l[stage as usize];
            let (t, n) = c.get();
            c.set((t + ticks, n + 1));
        });
    }

    pub fn flush() {
        LOCAL.with(|l| {
            for (i, c) in l.iter().enumerate() {
                let (t, n) = c.replace((0, 0));
                TICKS[i].fetch_add(t, Ordering::Relaxed);
                CALLS[i].fetch_add(n, Ordering::Relaxed);
            }
        });
        LOCAL_VISITS.with(|l| {
            for (i, c) in l.iter().enumerate() {
                VISITS[i].fetch_add(c.replace(0), Ordering::Relaxed);
            }
        });
    }

    /// This thread's counts not yet flushed.
    #[cfg(test)]
    pub fn local(stage: Stage) -> (u64, u64) {
        LOCAL.with(|l| l[stage as usize].get())
    }

    pub fn take() -> Vec<StageTime> {
        Stage::ALL
            .iter()
            .map(|&stage| StageTime {
                stage,
                ticks: TICKS[stage as usize].swap(0, Ordering::Relaxed),
                calls: CALLS[stage as usize].swap(0, Ordering::Relaxed),
            })
            .collect()
    }
}

#[cfg(all(test, feature = "stage-timing"))]
mod tests {
    use super::*;

    /// The walk counts what it visits, per thread: over one triangle (a
    /// root node whose one slot is a one-triangle leaf), a ray that hits
    /// visits the root and the leaf; a ray that passes beside it, the root
    /// only; a flush moves the counts into the totals.
    #[test]
    fn stages_count_the_walks_visits() {
        use crate::accel::{Accel, BuildQuality};
        use crate::ray::Ray;
        use glam::Vec3;
        let accel = Accel::build(&[[Vec3::ZERO, Vec3::X, Vec3::Y]], BuildQuality::Medium);
        flush();
        let ray = |x: f32| Ray::new(Vec3::new(x, 0.25, 1.0), -Vec3::Z);
        assert!(accel.intersect(&ray(0.25)).is_some());
        let one = Visits {
            nodes: 1,
            leaves: 1,
            triangles: 1,
        };
        assert_eq!(counter::local_visits(), one);
        assert!(accel.intersect(&ray(5.0)).is_none());
        assert_eq!(counter::local_visits(), Visits { nodes: 2, ..one });
        take_visits();
        flush();
        assert_eq!(counter::local_visits(), Visits::default());
        let totals = take_visits().expect("the feature is on");
        assert!(totals.nodes >= 2 && totals.leaves >= 1, "{totals:?}");
    }

    /// Calls are counted per stage and thread, a stage's time holds the
    /// stages nested in it, and a flush moves the thread's counts into the
    /// totals (which other tests' threads may add to meanwhile: those are
    /// checked as lower bounds).
    #[test]
    fn stages_count_calls_and_nest() {
        flush();
        let spin = |n: u64| (0..n).fold(1u64, |a, i| std::hint::black_box(a.wrapping_mul(i | 1)));
        for _ in 0..500 {
            timed(Stage::Scatter, || {
                timed(Stage::Shading, || spin(200));
                spin(200)
            });
        }
        timed(Stage::Shadow, || spin(10));
        let (scatter, shading, shadow) = (
            counter::local(Stage::Scatter),
            counter::local(Stage::Shading),
            counter::local(Stage::Shadow),
        );
        assert_eq!((scatter.1, shading.1, shadow.1), (500, 500, 1));
        assert_eq!(counter::local(Stage::Sample), (0, 0));
        assert!(
            shading.0 > 0 && scatter.0 > shading.0,
            "{scatter:?} {shading:?}"
        );
        take();
        flush();
        assert_eq!(counter::local(Stage::Scatter), (0, 0));
        let totals = take().expect("the feature is on");
        let of = |s: Stage| totals.iter().find(|x| x.stage == s).copied().unwrap();
        assert!(of(Stage::Scatter).calls >= 500 && of(Stage::Scatter).ticks >= scatter.0);
        assert!(of(Stage::Shadow).calls >= 1);
    }
}
