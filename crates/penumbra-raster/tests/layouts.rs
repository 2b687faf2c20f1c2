//! Every `#[repr(C)]` struct the host shares with a shader has the field
//! names, offsets and size of its WGSL struct, as naga lays it out (WGSL
//! alignment rules: vec3 aligned to 16, struct size rounded to its alignment).

mod common;

use naga::proc::Layouter;
use penumbra_raster::gpu::{HostLayout, gpu_constants, gpu_structs};
use penumbra_raster::shaders::{all_modules, forward_source, with_library};
use std::collections::BTreeMap;

/// (size, [(member name, offset)]) of every named struct in `source`.
fn wgsl_structs(source: &str) -> BTreeMap<String, (u32, Vec<(String, u32)>)> {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("WGSL does not parse: {}", e.emit_to_string(source)));
    let mut layouter = Layouter::default();
    layouter.update(module.to_ctx()).expect("layout");
    let mut out = BTreeMap::new();
    for (handle, ty) in module.types.iter() {
        if let (Some(name), naga::TypeInner::Struct { members, span }) = (&ty.name, &ty.inner) {
            assert_eq!(layouter[handle].size, *span, "{name}: layouter vs span");
            let fields = members
                .iter()
                .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                .collect();
            out.insert(name.clone(), (*span, fields));
        }
    }
    out
}

/// Compares every host struct that `source` declares (with `all`, every
/// host struct must be declared) and returns the names compared.
fn check_some(host: &[HostLayout], source: &str, all: bool) -> Vec<&'static str> {
    let wgsl = wgsl_structs(source);
    let mut compared = Vec::new();
    for h in host {
        let Some((size, fields)) = wgsl.get(h.wgsl_name) else {
            assert!(!all, "no WGSL struct {}", h.wgsl_name);
            continue;
        };
        compared.push(h.wgsl_name);
        let host_fields: Vec<(String, u32)> = h
            .fields
            .iter()
            .map(|(n, o)| (n.to_string(), *o as u32))
            .collect();
        assert_eq!(
            &host_fields, fields,
            "{}: host (name, offset) vs WGSL",
            h.wgsl_name
        );
        assert_eq!(h.size as u32, *size, "{}: host size vs WGSL", h.wgsl_name);
    }
    compared
}

fn check(host: &[HostLayout], source: &str) -> usize {
    check_some(host, source, true).len()
}

#[test]
fn every_pass_module_validates_and_its_structs_match_the_host() {
    let host = gpu_structs();
    let mut seen = std::collections::BTreeSet::new();
    for (name, source) in all_modules() {
        let module = naga::front::wgsl::parse_str(&source)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
        // Each module's structs match their host twins (a module that uses
        // a struct declares it); below, every host struct is in some module.
        seen.extend(check_some(&host, &source, false));
        // Every struct named Gpu* in the shaders is uploaded by the host, so
        // it must have a host twin in the list.
        for struct_name in wgsl_structs(&source).keys() {
            if struct_name.starts_with("Gpu") {
                assert!(
                    host.iter().any(|h| h.wgsl_name == struct_name),
                    "{name}: WGSL struct {struct_name} has no #[repr(C)] host twin in gpu_structs()"
                );
            }
        }
    }
    for h in &host {
        assert!(
            seen.contains(h.wgsl_name),
            "{} is in no module",
            h.wgsl_name
        );
    }
}

#[test]
fn test_kernel_structs_match_wgsl() {
    let mut host = common::test_structs();
    host.extend(
        gpu_structs()
            .into_iter()
            .filter(|h| h.wgsl_name == "GpuLight" || h.wgsl_name == "GpuMaterial"),
    );
    check(&host, &with_library(common::KERNELS_WGSL));
}

#[test]
fn layout_check_detects_a_mismatch() {
    // The comparison itself must be able to fail: a host struct that packs
    // the vec3 `emission` right after `ks` (offset 44, not 16-aligned) does
    // not match.
    let wrong = HostLayout {
        wgsl_name: "GpuMaterial",
        size: 128,
        fields: vec![
            ("model", 0),
            ("variant", 4),
            ("shininess", 8),
            ("double_sided", 12),
            ("kd", 16),
            ("alpha", 28),
            ("ks", 32),
            ("ior", 44),
            ("emission", 44),
            ("roughness", 60),
            ("base_color", 64),
            ("metallic", 76),
            ("specular_color", 80),
            ("transmission", 92),
            ("conductor_eta", 96),
            ("specular", 108),
            ("conductor_k", 112),
            ("_pad0", 124),
        ],
    };
    let r = std::panic::catch_unwind(|| check(&[wrong], &forward_source()));
    assert!(r.is_err());
}

/// The constants the host shares with the forward shaders have the host's
/// values there.
#[test]
fn shared_constants_match_the_host() {
    let source = forward_source();
    let module = naga::front::wgsl::parse_str(&source)
        .unwrap_or_else(|e| panic!("WGSL does not parse: {}", e.emit_to_string(&source)));
    for (name, value) in gpu_constants() {
        let constant = module
            .constants
            .iter()
            .map(|(_, c)| c)
            .find(|c| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no WGSL constant {name}"));
        let wgsl = match module.global_expressions[constant.init] {
            naga::Expression::Literal(naga::Literal::U32(v)) => v,
            ref e => panic!("{name}: not a u32 literal: {e:?}"),
        };
        assert_eq!(wgsl, value, "{name}: WGSL vs host");
    }
}
