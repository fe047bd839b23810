//! Regions of a picture or an outline meshed one by one and merged: what
//! [`super::mesh_image`] and the simulation mesh ([`super::nested`]) share.

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::meshing::outline::{mesh_outline, OutlineOptions};

/// Meshes each region of `components` (an outer loop of `loops` with its holes) with
/// `options`; a region whose loops do not mesh (should simplification have broken them)
/// is meshed from the same loops of `fallback` instead. Errors: those of [`mesh_outline`].
pub(crate) fn mesh_regions(
    loops: &[Vec<[f64; 2]>],
    fallback: &[Vec<[f64; 2]>],
    components: &[(usize, Vec<usize>)],
    options: &OutlineOptions,
) -> Result<Vec<Mesh>> {
    let pick = |from: &[Vec<[f64; 2]>], holes: &[usize]| -> Vec<Vec<[f64; 2]>> {
        holes.iter().map(|&k| from[k].clone()).collect()
    };
    components
        .iter()
        .map(|(outer, holes)| match mesh_outline(&loops[*outer], &pick(loops, holes), options) {
            Err(Error::BadOutline { .. }) => mesh_outline(&fallback[*outer], &pick(fallback, holes), options),
            other => other,
        })
        .collect()
}

/// The meshes as one mesh (one component each, vertices numbered in order).
pub(crate) fn merge(meshes: Vec<Mesh>) -> Result<Mesh> {
    if meshes.len() == 1 {
        return meshes.into_iter().next().ok_or(Error::EmptyMesh);
    }
    let mut vertices = Vec::with_capacity(meshes.iter().map(|m| m.vertices().len()).sum());
    let mut triangles = Vec::with_capacity(meshes.iter().map(|m| m.triangles().len()).sum());
    for m in &meshes {
        let base = vertices.len() as u32;
        vertices.extend_from_slice(m.vertices());
        triangles.extend(m.triangles().iter().map(|t| t.map(|v| v + base)));
    }
    Mesh::new(vertices, triangles)
}
