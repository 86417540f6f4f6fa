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

/// Loads a mesh file for an object type: as the convex hull of its vertices, or as a triangle
/// mesh (all meshes of the file merged). Errors name the file.
pub fn load_mesh_file(path: &Path, as_convex_hull: bool) -> Result<Shape, String> {
    let filename = path.to_string_lossy();
    if as_convex_hull {
        return load_convex_hull(&filename, Vec3::new(1.0, 1.0, 1.0), None);
    }
    let scene = mesh_loader::Loader::default()
        .merge_meshes(true)
        .load(path)
        .map_err(|error| format!("{}: {error}", path.display()))?;
    let mut vertices = Vec::new();
    let mut triangles = Vec::new();
    for mesh in &scene.meshes {
        let offset = u32::try_from(vertices.len())
            .map_err(|_| format!("{}: too many vertices", path.display()))?;
        vertices.extend(
            mesh.vertices
                .iter()
                .map(|v| Point3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]))),
        );
        triangles.extend(mesh.faces.iter().map(|f| [f[0] + offset, f[1] + offset, f[2] + offset]));
    }
    if triangles.is_empty() {
        return Err(format!("{}: the mesh has no triangles", path.display()));
    }
    if !vertices.iter().all(|point| point.iter().all(|value| value.is_finite())) {
        return Err(format!("{}: non-finite vertex", path.display()));
    }
    Ok(Shape::TriMesh { vertices, triangles })
}
