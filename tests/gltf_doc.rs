//! glTF documents written by the tests: one base64 buffer, meshes, materials, nodes, cameras and lights.

#![allow(dead_code)]

use crate::common::scratch;
use base64::Engine as _;
use std::fmt::Write as _;
use std::path::PathBuf;

/// A glTF document assembled in memory: one base64 buffer, views and accessors appended as data is added.
#[derive(Default)]
pub struct Doc {
    pub buf: Vec<u8>,
    pub views: Vec<String>,
    pub accessors: Vec<String>,
    pub meshes: Vec<String>,
    pub materials: Vec<String>,
    pub nodes: Vec<String>,
    pub cameras: Vec<String>,
    pub lights: Vec<String>,
    pub extra: String,
}

impl Doc {
    pub fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.buf.len().is_multiple_of(4) {
            self.buf.push(0);
        }
        self.views.push(format!(
            "{{\"buffer\": 0, \"byteOffset\": {}, \"byteLength\": {}}}",
            self.buf.len(),
            bytes.len()
        ));
        self.buf.extend_from_slice(bytes);
        self.views.len() - 1
    }

    pub fn floats(&mut self, v: &[f32], ty: &str) -> usize {
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        let n = match ty {
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            _ => 1,
        };
        let view = self.view(&bytes);
        // POSITION accessors must state their bounds.
        let bounds = if n == 3 {
            let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
            for c in v.chunks_exact(3) {
                for k in 0..3 {
                    lo[k] = lo[k].min(c[k]);
                    hi[k] = hi[k].max(c[k]);
                }
            }
            let fmt = |a: [f32; 3]| a.map(|x| if x.is_finite() { x } else { 0.0 });
            format!(", \"min\": {:?}, \"max\": {:?}", fmt(lo), fmt(hi))
        } else {
            String::new()
        };
        self.accessors.push(format!(
            "{{\"bufferView\": {view}, \"componentType\": 5126, \"count\": {}, \"type\": \"{ty}\"{bounds}}}",
            v.len() / n
        ));
        self.accessors.len() - 1
    }

    pub fn indices(&mut self, v: &[u32]) -> usize {
        let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.accessors.push(format!(
            "{{\"bufferView\": {view}, \"componentType\": 5125, \"count\": {}, \"type\": \"SCALAR\"}}",
            v.len()
        ));
        self.accessors.len() - 1
    }

    /// A mesh of one triangle primitive; returns its index.
    pub fn mesh(&mut self, positions: &[f32], indices: &[u32], material: usize) -> usize {
        let p = self.floats(positions, "VEC3");
        let i = self.indices(indices);
        self.meshes.push(format!("{{\"primitives\": [{{\"attributes\": {{\"POSITION\": {p}}}, \"indices\": {i}, \"material\": {material}}}]}}"));
        self.meshes.len() - 1
    }

    pub fn json(&self) -> String {
        let uri = base64::engine::general_purpose::STANDARD.encode(&self.buf);
        let list = |v: &[String]| v.join(",\n");
        let mut s = format!(
            "{{\"asset\": {{\"version\": \"2.0\"}}, \"scene\": 0, \"scenes\": [{{\"nodes\": [{}]}}],\n\"nodes\": [{}],\n\"meshes\": [{}],\n\"materials\": [{}],\n\"accessors\": [{}],\n\"bufferViews\": [{}],\n\"buffers\": [{{\"byteLength\": {}, \"uri\": \"data:application/octet-stream;base64,{uri}\"}}]",
            (0..self.nodes.len()).map(|i| i.to_string()).collect::<Vec<_>>().join(", "),
            list(&self.nodes),
            list(&self.meshes),
            list(&self.materials),
            list(&self.accessors),
            list(&self.views),
            self.buf.len()
        );
        if !self.cameras.is_empty() {
            let _ = write!(s, ",\n\"cameras\": [{}]", list(&self.cameras));
        }
        if !self.lights.is_empty() {
            let _ = write!(
                s,
                ",\n\"extensionsUsed\": [\"KHR_lights_punctual\", \"KHR_materials_specular\", \"KHR_materials_emissive_strength\"], \"extensions\": {{\"KHR_lights_punctual\": {{\"lights\": [{}]}}}}",
                list(&self.lights)
            );
        } else {
            s.push_str(",\n\"extensionsUsed\": [\"KHR_materials_specular\", \"KHR_materials_emissive_strength\"]");
        }
        s.push_str(&self.extra);
        s.push('}');
        s
    }

    pub fn write(&self, name: &str) -> PathBuf {
        let p = scratch("gltf").join(name);
        std::fs::write(&p, self.json()).unwrap();
        p
    }
}

pub const QUAD: [f32; 12] = [-1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0];
pub const QUAD_IDX: [u32; 6] = [0, 1, 2, 0, 2, 3];

/// A diffuse glTF material: KHR_materials_specular with factor 0 removes the dielectric coat (pure Lambert).
pub fn diffuse(c: [f32; 3], double_sided: bool, emission: Option<[f32; 3]>) -> String {
    let mut s = format!(
        "{{\"pbrMetallicRoughness\": {{\"baseColorFactor\": [{}, {}, {}, 1], \"metallicFactor\": 0, \"roughnessFactor\": 1}}, \"doubleSided\": {double_sided}, \"extensions\": {{\"KHR_materials_specular\": {{\"specularFactor\": 0}}",
        c[0], c[1], c[2]
    );
    if let Some(e) = emission {
        let m = e.iter().cloned().fold(0.0, f32::max);
        let _ = write!(
            s,
            ", \"KHR_materials_emissive_strength\": {{\"emissiveStrength\": {m}}}}}, \"emissiveFactor\": [{}, {}, {}]}}",
            e[0] / m,
            e[1] / m,
            e[2] / m
        );
    } else {
        s.push_str("}}");
    }
    s
}

pub fn node(mesh: usize, t: [f32; 3], axis_deg: Option<([f32; 3], f32)>, s: [f32; 3]) -> String {
    let r = match axis_deg {
        None => [0.0, 0.0, 0.0, 1.0],
        Some((a, d)) => {
            let h = (d.to_radians() * 0.5).sin();
            [a[0] * h, a[1] * h, a[2] * h, (d.to_radians() * 0.5).cos()]
        }
    };
    format!("{{\"mesh\": {mesh}, \"translation\": {t:?}, \"rotation\": {r:?}, \"scale\": {s:?}}}")
}
