//! Pictures of the learned regions: for every type pair with regions, samples drawn from each
//! region's mixture in the primary's frame, around the primary's outline (the paper's Figure 5).
//!
//! Samples come from a generator seeded by the spec's seed, one stream per pair in pair order,
//! so the pictures are as reproducible as the PDDL.

use std::path::PathBuf;

use lamp_geometry::{Pose, Shape};
use lamp_learn::Model;
use lamp_render::{RegionPlot, RenderOptions, SampleSet, render_regions};
use lamp_world::SpecWorld;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::model_folder::ArtifactFile;

/// The folder of the region pictures inside the build folder.
pub const REGIONS_DIR: &str = "regions";
/// Samples drawn per region.
pub const SAMPLES_PER_REGION: usize = 300;

/// One SVG per type pair with regions, named `regions/<primary>_<secondary>.svg`.
pub fn region_plots(model: &Model, world: &SpecWorld, seed: u64) -> Vec<ArtifactFile> {
    model
        .pairs
        .iter()
        .enumerate()
        .map(|(index, learned)| {
            let pair = &learned.pair.pair;
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            rng.set_stream(index as u64);
            let sets = learned
                .regions
                .iter()
                .map(|region| SampleSet {
                    label: region.relation.clone(),
                    poses: (0..SAMPLES_PER_REGION).map(|_| region.model.sample(&mut rng)).collect(),
                })
                .collect();
            let plot = RegionPlot {
                primary: pair.primary.clone(),
                secondary: pair.secondary.clone(),
                primary_parts: outline(world, &pair.primary),
                sets,
            };
            ArtifactFile {
                path: PathBuf::from(REGIONS_DIR).join(format!("{}.svg", pair.stem())),
                contents: render_regions(&plot, &RenderOptions::default()),
            }
        })
        .collect()
}

/// The shapes of a type in its own frame: an object type's parts, or a robot part's link
/// geometry (empty if neither is known, and the plot shows the origin only).
fn outline(world: &SpecWorld, type_name: &str) -> Vec<(Pose, Shape)> {
    if let Some(parts) = world.type_parts.get(type_name) {
        return parts.clone();
    }
    for robot in &world.spec().robots {
        let Some(part) = robot.parts.iter().find(|part| part.type_name == type_name) else {
            continue;
        };
        let Some(model) = world.robots.get(&robot.name) else { continue };
        let Some(link) = model.link_id(&part.link) else { continue };
        return model
            .collision_geometry()
            .iter()
            .filter(|geometry| geometry.link == link)
            .map(|geometry| (geometry.origin, geometry.shape.clone()))
            .collect();
    }
    Vec::new()
}
