//! Collision meshes (STL, OBJ, COLLADA) loaded as convex hulls, and URDF mesh path resolution.

use std::path::{Path, PathBuf};

use lamp_geometry::{Point3, Shape, Vec3};

/// Loads every vertex of a mesh file (scaled) as the point cloud of a convex hull.
pub(crate) fn load_convex_hull(
    filename: &str,
    scale: Vec3,
    base_dir: Option<&Path>,
) -> Result<Shape, String> {
    if !scale.iter().all(|value| value.is_finite() && *value != 0.0) {
        return Err(format!(
            "scale ({}, {}, {}) must be finite and non-zero",
            scale.x, scale.y, scale.z
        ));
    }
    let path = resolve_mesh_path(filename, base_dir)?;
    let scene = mesh_loader::Loader::default()
        .merge_meshes(true)
        .load(&path)
        .map_err(|error| format!("{}: {error}", path.display()))?;
    let mut points: Vec<Point3> = scene
        .meshes
        .iter()
        .flat_map(|mesh| mesh.vertices.iter())
        .map(|vertex| {
            Point3::new(
                f64::from(vertex[0]) * scale.x,
                f64::from(vertex[1]) * scale.y,
                f64::from(vertex[2]) * scale.z,
            )
        })
        .collect();
    if !points.iter().all(|point| point.iter().all(|value| value.is_finite())) {
        return Err(format!("{}: non-finite vertex", path.display()));
    }
    // STL repeats each vertex once per adjacent triangle; duplicates add nothing to a hull.
    points.sort_by(|a, b| {
        a.iter()
            .zip(b.iter())
            .map(|(x, y)| x.total_cmp(y))
            .find(|order| order.is_ne())
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    points.dedup();
    if points.len() < 4 {
        return Err(format!("{}: fewer than 4 distinct vertices, no volume", path.display()));
    }
    Ok(Shape::ConvexHull { points })
}

/// Resolves a URDF mesh reference: `package://NAME/rest` (a folder NAME at or above the URDF's
/// folder, or the URDF's folder itself), `file://` absolute paths, and paths relative to the URDF.
pub(crate) fn resolve_mesh_path(
    filename: &str,
    base_dir: Option<&Path>,
) -> Result<PathBuf, String> {
    if let Some(rest) = filename.strip_prefix("package://") {
        let (package, relative) = rest
            .split_once('/')
            .ok_or_else(|| "package URL has no path after the package name".to_string())?;
        let base = base_dir
            .ok_or_else(|| "no base directory to resolve a package:// path against".to_string())?;
        let mut candidates = Vec::new();
        for ancestor in base.ancestors() {
            if ancestor.file_name().is_some_and(|name| name == package) {
                candidates.push(ancestor.join(relative));
            }
            candidates.push(ancestor.join(package).join(relative));
        }
        candidates.push(base.join(relative));
        return candidates.into_iter().find(|candidate| candidate.is_file()).ok_or_else(|| {
            format!("package `{package}` not found at or above {}", base.display())
        });
    }
    let plain = filename.strip_prefix("file://").unwrap_or(filename);
    let path = Path::new(plain);
    let resolved = if path.is_absolute() {
        path.to_path_buf()
    } else {
        base_dir
            .ok_or_else(|| {
                "relative mesh path but no base directory to resolve it against".to_string()
            })?
            .join(path)
    };
    if resolved.is_file() {
        Ok(resolved)
    } else {
        Err(format!("file {} does not exist", resolved.display()))
    }
}
