//! The regions of a [`super::SurfaceDeformer`]: the fixed vertices and the handles, given as
//! the caller's vertex indices, checked and mapped onto the welded surface.

use super::mesh3::Surface3;
use crate::limits::MAX_VERTICES;
use crate::{Error, Result};

/// The most handles a [`super::SurfaceDeformer`] compiles (each adds a harmonic field and
/// a value per triangle read in every update).
pub const MAX_SURFACE_HANDLES: usize = 64;

/// A welded vertex's role: free, fixed at rest, or in handle `k`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Role {
    /// Solved for.
    Free,
    /// Held at rest: a `fixed` vertex, or the first vertex of a connected piece that no
    /// region reaches (which then stays at rest).
    Fixed,
    /// Moved by handle `k`'s matrix.
    Handle(usize),
}

/// Each welded vertex's [`Role`], from the caller's `fixed` and `handles`.
///
/// Errors, before any work beyond the checks: [`Error::BadOption`] (`handles`) for no
/// handle or more than [`MAX_SURFACE_HANDLES`]; [`Error::TooMany`] for a list longer than
/// [`MAX_VERTICES`]; [`Error::BadRegion`] for an index out of range, or a vertex (or its
/// welded seam twin) in two regions.
pub(crate) fn roles(surface: &Surface3, fixed: &[u32], handles: &[&[u32]]) -> Result<Vec<Role>> {
    if handles.is_empty() || handles.len() > MAX_SURFACE_HANDLES {
        return Err(Error::BadOption {
            name: "handles",
            value: Some(handles.len() as f64),
            reason: format!("handles given: from 1 to {MAX_SURFACE_HANDLES} are needed"),
        });
    }
    let lists = std::iter::once(("fixed".to_string(), fixed))
        .chain(handles.iter().enumerate().map(|(k, h)| (format!("handles[{k}]"), *h)));
    for (name, list) in lists.clone() {
        if list.len() > MAX_VERTICES {
            let (what, count) = (region_items(&name), list.len() as f64);
            return Err(Error::TooMany { what, count, estimated: false, limit: MAX_VERTICES });
        }
    }
    let n = surface.caller_vertex_count();
    let weld = surface.weld_map();
    let mut role = vec![Role::Free; surface.vertices().len()];
    let mut owner: Vec<Option<String>> = vec![None; role.len()];
    for (k, (name, list)) in lists.enumerate() {
        let this = if k == 0 { Role::Fixed } else { Role::Handle(k - 1) };
        for (index, &vertex) in list.iter().enumerate() {
            let bad = |reason: String| Error::BadRegion { region: name.clone(), index, vertex, reason };
            if vertex as usize >= n {
                return Err(bad(format!("is not a vertex index (there are {n} vertices)")));
            }
            let w = weld[vertex as usize] as usize;
            match role[w] {
                Role::Free => {
                    role[w] = this;
                    owner[w] = Some(name.clone());
                }
                r if r == this => {}
                _ => {
                    let other = owner[w].clone().unwrap_or_default();
                    return Err(bad(format!("is already in {other} (itself or a vertex welded to it)")));
                }
            }
        }
    }
    hold_unreached_pieces(surface, &mut role);
    Ok(role)
}

/// What a region's list holds, for [`Error::TooMany`].
fn region_items(name: &str) -> &'static str {
    if name == "fixed" {
        "fixed vertices"
    } else {
        "handle vertices"
    }
}

/// Fixes the first vertex of every connected piece that has no constrained vertex, so that
/// the piece stays at rest (its harmonic fields are zero, its guidance the identity).
fn hold_unreached_pieces(surface: &Surface3, role: &mut [Role]) {
    let mut sets = crate::topology::UnionFind::new(role.len());
    for tri in surface.triangles() {
        sets.union(tri[0], tri[1]);
        sets.union(tri[1], tri[2]);
    }
    let mut reached = vec![false; role.len()];
    for (v, r) in role.iter().enumerate() {
        if *r != Role::Free {
            reached[sets.find(v as u32) as usize] = true;
        }
    }
    for (v, r) in role.iter_mut().enumerate() {
        let root = sets.find(v as u32) as usize;
        if !reached[root] {
            reached[root] = true;
            *r = Role::Fixed;
        }
    }
}
