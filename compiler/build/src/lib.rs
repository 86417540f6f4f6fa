//! lamp-build: the build pipeline behind `lampc build`.
//!
//! Before anything is read, every problem's initial scene is checked ([`initial_scene`]): one the
//! solver cannot start from refuses the build. Demonstration files (MCAP, read by
//! lamp-trajectory) become the learner's demonstrations through the [`adapter`], checked against
//! the spec; the spec's `learn` block becomes the learner's
//! configuration ([`config`]) and the spec's object shapes its capacity oracle ([`shapes`]);
//! the learned model becomes the artifacts: the PDDL domain with
//! provenance, one PDDL problem per spec problem whose goal can be written ([`problems`], with
//! [`aliases`] bound to learned regions), the sampler file ([`samplers`]), the vocabulary report
//! and the [`manifest`] with every artifact's digest, which the run time checks before it trusts
//! the build folder.
//!
//! The crate is pure: it takes files already read into memory ([`DemoFile`]) and returns every
//! artifact's text ([`Artifacts`]); reading, globbing, writing and printing are the caller's.
//! The only files it opens are the robot and mesh files the spec names, through lamp-world.

pub mod adapter;
pub mod aliases;
pub mod at_goals;
pub mod config;
pub mod digest;
pub mod error;
pub mod goal_warning;
pub mod grasps;
pub mod initial_scene;
pub mod input;
pub mod manifest;
pub mod model_folder;
pub mod pipeline;
pub mod problems;
pub mod provenance;
pub mod region_plots;
pub mod ros2;
pub mod samplers;
pub mod scene_issue;
pub mod shapes;
pub mod spec_sources;
pub mod structure_goals;
pub mod structure_issue;

pub use adapter::{Adapter, ros2_demo_file, ros2_demonstration};
pub use aliases::{ResolvedAlias, resolve_alias, resolve_aliases};
pub use at_goals::at_goal_atoms;
pub use config::learn_config;
pub use digest::{Digest, demonstration_digest, file_digest};
pub use error::BuildError;
pub use goal_warning::{GoalPlace, GoalWarning};
pub use grasps::{GrabDistanceWarning, grasps_outside_grab_distance};
pub use initial_scene::{
    CONTACT_TOLERANCE, MAX_DISTANCE, SceneIssue, check_initial_scenes, initial_scene_issues,
    problem_scene_issues,
};
pub use input::{DEFAULT_BUILD_DIR, DemoFile, SIMULATED_DEMOS_DIR, demo_name, demo_patterns};
pub use manifest::{
    BuildFolderError, MANIFEST_DIGEST, MANIFEST_FILE, MANIFEST_FORMAT, MANIFEST_VERSION, Manifest,
    ManifestEntry, check_same_demonstrations,
};
pub use pipeline::{
    ArtifactFile, Artifacts, BuildContext, DOMAIN_FILE, FAILED_DIR, MODEL_DIR, MODEL_FILE_LIMIT,
    PROBLEMS_DIR, SAMPLERS_FILE, Summary, VOCABULARY_FILE, artifacts, build, learn_model,
    learned_vocabulary,
};
pub use problems::{ProblemOutcome, problem_pddl};
pub use provenance::Provenance;
pub use region_plots::{REGIONS_DIR, SAMPLES_PER_REGION, region_plots};
pub use ros2::{
    BagTally, FrameObject, FrameRobot, MAX_TREE_DEPTH, MappedRobot, Ros2Bag, Ros2Error,
    Ros2Mapping, ros2_bag, ros2_trajectory,
};
pub use samplers::{SAMPLERS_FORMAT, SAMPLERS_VERSION, SamplersFile};
pub use scene_issue::IssuePlace;
pub use shapes::SpecShapes;
pub use spec_sources::{ProblemSources, SpecSources};
pub use structure_goals::{StructureGoal, placed_structure_issues, structure_goal_atoms};
pub use structure_issue::StructureIssue;
