//! GPU time of each render or compute pass from timestamp queries (where the
//! adapter supports `TIMESTAMP_QUERY`): a begin/end pair per named pass,
//! resolved after the frame into milliseconds.

use crate::context::{GpuContext, GpuError};
use crate::renderer::map_read;
use std::cell::RefCell;

/// Most queries in one wgpu query set (2 per pass).
const MAX_QUERIES: u32 = 4096;

/// GPU time of one pass.
#[derive(Clone, Debug, PartialEq)]
pub struct PassTiming {
    /// What the pass does, e.g. `"forward"`, `"shadow map 3"`.
    pub name: String,
    pub ms: f64,
}

/// Hands out timestamp writes to the passes of one frame, in order.
#[derive(Debug)]
pub struct GpuTimer {
    queries: Option<(wgpu::QuerySet, wgpu::Buffer, wgpu::Buffer)>,
    capacity: u32,
    names: RefCell<Vec<String>>,
}

impl GpuTimer {
    /// A timer for up to `passes` passes (clamped to the query-set limit;
    /// further passes go untimed). Times nothing on adapters without
    /// timestamp queries.
    pub fn new(ctx: &GpuContext, passes: u32) -> Self {
        let device = &ctx.device;
        let count = (2 * passes.max(1)).min(MAX_QUERIES);
        let queries = device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY)
            .then(|| {
                let set = device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("pass timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count,
                });
                let bytes = 8 * count as u64;
                let buffer = |label, usage| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(label),
                        size: bytes,
                        usage,
                        mapped_at_creation: false,
                    })
                };
                let resolve = buffer(
                    "timestamps",
                    wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                );
                let read = buffer(
                    "timestamps read",
                    wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                );
                (set, resolve, read)
            });
        Self {
            queries,
            capacity: count / 2,
            names: RefCell::new(Vec::new()),
        }
    }

    /// Reserves the next begin/end pair for the pass `name`.
    fn next(&self, name: &str) -> Option<(&wgpu::QuerySet, u32)> {
        let (set, _, _) = self.queries.as_ref()?;
        let mut names = self.names.borrow_mut();
        let index = names.len() as u32;
        if index >= self.capacity {
            return None;
        }
        names.push(name.to_string());
        Some((set, 2 * index))
    }

    /// Timestamp writes for a render pass named `name`.
    pub fn render_pass(&self, name: &str) -> Option<wgpu::RenderPassTimestampWrites<'_>> {
        self.next(name)
            .map(|(query_set, i)| wgpu::RenderPassTimestampWrites {
                query_set,
                beginning_of_pass_write_index: Some(i),
                end_of_pass_write_index: Some(i + 1),
            })
    }

    /// Timestamp writes for a compute pass named `name`.
    pub fn compute_pass(&self, name: &str) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
        self.next(name)
            .map(|(query_set, i)| wgpu::ComputePassTimestampWrites {
                query_set,
                beginning_of_pass_write_index: Some(i),
                end_of_pass_write_index: Some(i + 1),
            })
    }

    /// Records the copy of the used queries into the readable buffer; call
    /// once, after the last timed pass.
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        let used = self.names.borrow().len() as u32;
        if let (Some((set, resolve, read)), true) = (&self.queries, used > 0) {
            encoder.resolve_query_set(set, 0..2 * used, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, read, 0, 16 * used as u64);
        }
    }

    /// The passes' GPU times, in the order they were named (empty without
    /// timestamp support). The frame must have been submitted.
    pub fn read(&self, ctx: &GpuContext) -> Result<Vec<PassTiming>, GpuError> {
        let names = self.names.borrow();
        let Some((_, _, read)) = &self.queries else {
            return Ok(Vec::new());
        };
        if names.is_empty() {
            return Ok(Vec::new());
        }
        let bytes = map_read(ctx, read)?;
        let t: &[u64] = bytemuck::cast_slice(&bytes);
        let period = ctx.queue.get_timestamp_period() as f64;
        Ok(names
            .iter()
            .enumerate()
            .map(|(i, name)| PassTiming {
                name: name.clone(),
                ms: t[2 * i + 1].saturating_sub(t[2 * i]) as f64 * period * 1e-6,
            })
            .collect())
    }
}

/// Sum of the times of the passes whose name starts with `prefix`, or None
/// when no such pass was timed.
pub fn total_ms(passes: &[PassTiming], prefix: &str) -> Option<f64> {
    let mut it = passes
        .iter()
        .filter(|p| p.name.starts_with(prefix))
        .peekable();
    it.peek()?;
    Some(it.map(|p| p.ms).sum())
}

/// The passes grouped by kind (the name without a trailing number, so
/// `"shadow map 0"` … `"shadow map 5"` form one group): (kind, passes,
/// total ms), in order of first appearance.
pub fn by_kind(passes: &[PassTiming]) -> Vec<(String, usize, f64)> {
    let mut groups: Vec<(String, usize, f64)> = Vec::new();
    for p in passes {
        let kind = p
            .name
            .trim_end_matches(|c: char| c.is_ascii_digit())
            .trim_end();
        match groups.iter_mut().find(|g| g.0 == kind) {
            Some(g) => {
                g.1 += 1;
                g.2 += p.ms;
            }
            None => groups.push((kind.to_string(), 1, p.ms)),
        }
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_group_by_name_without_trailing_number() {
        let p = |name: &str, ms| PassTiming {
            name: name.into(),
            ms,
        };
        let passes = [
            p("shadow map 0", 1.0),
            p("shadow map 1", 2.0),
            p("forward", 4.0),
            p("shadow map 12", 0.5),
        ];
        assert_eq!(
            by_kind(&passes),
            [
                ("shadow map".to_string(), 3, 3.5),
                ("forward".to_string(), 1, 4.0)
            ]
        );
        assert_eq!(total_ms(&passes, "shadow"), Some(3.5));
        assert_eq!(total_ms(&passes, "stencil"), None);
    }
}
