//! The human-readable vocabulary report (Markdown): what each invented relation and action means and where it came from.

use std::fmt::Write as _;

use crate::actions::Action;
use crate::capacity::SideReason;
use crate::learner::RegionSummary;
use crate::model::{LearnedPair, Model, Region};
use crate::selection::Selection;

/// Transitions listed per action before the rest are summarised as a count.
const LISTED_TRANSITIONS: usize = 12;

/// The vocabulary report of a model.
pub fn vocabulary_report(model: &Model) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "# Learned vocabulary\n");
    let _ = writeln!(
        out,
        "Learned from {} demonstrations with seed {}: {} relations over {} type pairs, {} actions.\n",
        model.demonstrations,
        model.seed,
        model.predicates().len(),
        model.pairs.len(),
        model.actions.len()
    );
    let _ = writeln!(
        out,
        "Relative poses are of the second type in the first type's frame; positions in metres, angles in degrees.\n"
    );
    let _ = writeln!(out, "## Relations\n");
    for pair in &model.pairs {
        pair_section(&mut out, pair);
    }
    if !model.pairs_without_regions.is_empty() {
        let names: Vec<String> =
            model.pairs_without_regions.iter().map(|p| format!("`{}`", p.stem())).collect();
        let _ = writeln!(
            out,
            "Type pairs without any critical region (no relations): {}.\n",
            names.join(", ")
        );
    }
    let _ = writeln!(out, "## Actions\n");
    rests_section(&mut out, model);
    for action in &model.actions {
        action_section(&mut out, action);
    }
    out
}

/// The demonstrations learned from only up to a grasp, when there are any.
fn rests_section(out: &mut String, model: &Model) {
    let rests = &model.undescribed_rests;
    if rests.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "{} of the {} demonstrations are learned from only up to a grasp: the object let go of afterwards came to rest against another with no learned relation between them, so an action learned from that placement would put it there with nothing to hold it (more demonstrations of that way of resting make its relation):\n",
        rests.len(),
        model.demonstrations
    );
    for rest in rests.iter().take(LISTED_TRANSITIONS) {
        let _ = writeln!(
            out,
            "- {}: `{}` let go of against `{}` at step {}; steps 0–{} kept",
            rest.demonstration,
            rest.object,
            rest.against,
            rest.release,
            rest.kept_steps.saturating_sub(1)
        );
    }
    if rests.len() > LISTED_TRANSITIONS {
        let _ = writeln!(out, "- and {} more", rests.len() - LISTED_TRANSITIONS);
    }
    let _ = writeln!(out);
}

fn pair_section(out: &mut String, learned: &LearnedPair) {
    let pair = &learned.pair;
    let settings = &pair.settings;
    let _ = writeln!(
        out,
        "### `{}`: {} relative to {}\n",
        pair.pair.stem(),
        pair.pair.secondary,
        pair.pair.primary
    );
    let _ = writeln!(
        out,
        "Bins {:?} over ±{:?} m, {} rotation bins, θ = {}, mixtures of up to {} components covering {} of their samples, seen in {} demonstrations.\n",
        settings.position_bins,
        settings.half_range,
        settings.rotation_bins,
        settings.threshold,
        settings.max_components,
        settings.cover,
        pair.demonstrations
    );
    if let Some(turn) = settings.free_turn {
        let (roll, pitch, yaw) = turn.reference.euler_angles();
        let _ = writeln!(
            out,
            "The {secondary} turns freely about its {axis} axis in every group: rotation cells are taken from the rotation {} {} {} (roll pitch yaw, degrees), with one bin for that turn.\n",
            rounded(roll.to_degrees(), 0),
            rounded(pitch.to_degrees(), 0),
            rounded(yaw.to_degrees(), 0),
            secondary = pair.pair.secondary,
            axis = ["x", "y", "z"][turn.axis],
        );
    }
    if let Some(symmetry) = &pair.symmetry {
        let turns = |count: usize, type_name: &str| match count {
            1 => format!("the {type_name} has none"),
            count => format!("the {type_name} {} about its vertical axis", plural_turns(count)),
        };
        let why = match &pair.symmetry_choice {
            Some(choice) => format!(
                "`symmetry auto`: folded, the demonstrations' rests make {} in place of {}, with {} keyframes in them against {}{}",
                counted(choice.places_folded, "place"),
                choice.places_as_recorded,
                choice.keyframes_folded,
                choice.keyframes_as_recorded,
                choice.uncovered.map_or_else(String::new, |[x, y, z]| format!(
                    ", and as recorded no place holds the rest a place shows at ({}, {}, {}) m, where a symmetric frame puts it",
                    rounded(x, 4),
                    rounded(y, 4),
                    rounded(z, 4),
                )),
            ),
            None => "`symmetry on`".to_string(),
        };
        let _ = writeln!(
            out,
            "Relative poses are compared up to the shapes' symmetries ({why}): {}, {}; every pose, centre and representative below is its orbit's representative.\n",
            turns(symmetry.primary.len(), &pair.pair.primary),
            turns(symmetry.secondary.len(), &pair.pair.secondary),
        );
    } else if let Some(choice) = &pair.symmetry_choice {
        let why = match choice.lost {
            Some([x, y, z]) => format!(
                "folding would lose the place at ({}, {}, {}) m, which no folded place holds",
                rounded(x, 4),
                rounded(y, 4),
                rounded(z, 4),
            ),
            None if choice.places_folded == 0 && choice.places_as_recorded == 0 => {
                "neither way finds a place".to_string()
            }
            None => format!(
                "folded, the demonstrations' rests make {} with {} keyframes in them, as recorded {} with {}: nothing gained",
                counted(choice.places_folded, "place"),
                choice.keyframes_folded,
                counted(choice.places_as_recorded, "place"),
                choice.keyframes_as_recorded,
            ),
        };
        let _ = writeln!(
            out,
            "Relative poses are compared as recorded, not up to the shapes' symmetries (`symmetry auto`): {why}.\n",
        );
    }
    if let Some(selection) = &pair.selection {
        selection_section(out, selection);
    }
    let _ = writeln!(
        out,
        "| relation | g | centre | spread | representative pose (xyz; roll pitch yaw) | cells | components | demonstrations | time steps |"
    );
    let _ = writeln!(out, "| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for region in &learned.regions {
        region_row(out, region);
    }
    let (primary, secondary) = (&pair.pair.primary, &pair.pair.secondary);
    let _ = writeln!(
        out,
        "\n- `{}_0({primary}, {secondary})`: the {secondary} is in none of these regions.",
        pair.pair.stem()
    );
    for region in &learned.regions {
        let _ = writeln!(out, "{}", side_line(primary, secondary, region, true));
        let _ = writeln!(out, "{}", side_line(primary, secondary, region, false));
    }
    let _ = writeln!(out);
}

/// What the selection chose for a pair and the evidence that chose it, so that a user can pin it.
fn selection_section(out: &mut String, selection: &Selection) {
    let chosen = selection.chosen;
    let names: Vec<&str> = [
        (chosen.position_bins, "position bins"),
        (chosen.half_range, "range"),
        (chosen.rotation_bins, "rotation bins"),
        (chosen.threshold, "threshold"),
    ]
    .into_iter()
    .filter_map(|(was_chosen, name)| was_chosen.then_some(name))
    .collect();
    let settings = &selection.settings;
    let [x, y, z] = settings.half_range;
    let [nx, ny, nz] = settings.position_bins;
    let _ = writeln!(
        out,
        "Chosen from the demonstrations: {} (to pin them: `position bins ({nx}, {ny}, {nz}) range ({x:.4}, {y:.4}, {z:.4}) m  rotation bins {}  threshold {:.4}`).",
        names.join(", "),
        settings.rotation_bins,
        settings.threshold
    );
    if !selection.boxes.is_empty() {
        let _ = writeln!(
            out,
            "No uniform grid keeps the groups apart (the finest that keeps each group whole puts some in one cell), so each place is a box of its own, the group's extent with its tolerance: {} boxes in place of those bins (pinned bins bring the grid back).",
            selection.boxes.len()
        );
    }
    let _ = writeln!(
        out,
        "{} keyframes (still: under {:.3} mm and {:.4}° a step); {} kept, {} left out for too little support; least margin of a group from its cell's edges per axis {:.2}, {:.2}, {:.2} of a cell.
",
        selection.keyframes,
        selection.stillness.position * 1000.0,
        selection.stillness.rotation.to_degrees(),
        counted(selection.groups.len(), "group"),
        selection.dropped,
        selection.margins[0],
        selection.margins[1],
        selection.margins[2]
    );
    if let Some(apart) = selection.apart {
        let _ = writeln!(
            out,
            "Both are movable objects, so only keyframes at which they touch count (within the release tolerance): {apart} left out where they were apart.
"
        );
    }
    let fixed: Vec<&str> = ["x", "y", "z"]
        .into_iter()
        .zip(selection.fixed_axes)
        .filter_map(|(name, fixed)| fixed.then_some(name))
        .collect();
    if !fixed.is_empty() {
        let _ = writeln!(
            out,
            "No demonstration moves the pair along {}: one cell spans every value seen there.
",
            fixed.join(", ")
        );
    }
    if selection.groups.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "| group | g | demonstrations | keyframes | scale | centre | extent | tolerance | cell share |"
    );
    let _ = writeln!(out, "| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for (index, group) in selection.groups.iter().enumerate() {
        let extent: Vec<String> =
            (0..3).map(|axis| format!("{:.4}", group.high[axis] - group.low[axis])).collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {:.0} mm | {} | {} | {:.0} mm | {:.3} |",
            index + 1,
            group.g,
            group.demonstrations,
            group.keyframes(),
            group.scale * 1000.0,
            vector(&group.centre),
            extent.join(", "),
            group.tolerance * 1000.0,
            group.share
        );
    }
    let _ = writeln!(out);
}

fn vector(values: &[f64; 3]) -> String {
    format!("{:.4}, {:.4}, {:.4}", values[0], values[1], values[2])
}

/// What one side's relation of a region means (`clear_…` when `clear`, else `nowhere_…`), or why it does not exist.
fn side_line(primary: &str, secondary: &str, region: &Region, clear: bool) -> String {
    let k = region.index;
    let sides = &region.summary.sides;
    let (word, side) = if clear { ("clear", sides.clear) } else { ("nowhere", sides.nowhere) };
    let name = format!("{word}_{}", region.relation);
    // The type whose capacity is in question, and the one whose region holds it.
    let (many, holder) = if clear {
        (format!("two {}", plural(secondary)), format!("a {primary}"))
    } else {
        (format!("a {secondary}"), format!("two {}", plural(primary)))
    };
    let why = match side.reason {
        SideReason::Setting => format!("`{word} {}`", if side.on { "on" } else { "off" }),
        SideReason::TwoFit if clear => format!("{many} fit in region {k} of {holder} at once"),
        SideReason::TwoFit => format!("{many} can be in region {k} of {holder} at once"),
        SideReason::OneAtATime => format!("{many} cannot be in region {k} of {holder} at once"),
        SideReason::RobotPart if clear => {
            format!("the {primary} is a robot part and goes to one {secondary} at a time")
        }
        SideReason::UnknownShape | SideReason::RobotPart => {
            format!("the {}'s shape is unknown", if clear { secondary } else { primary })
        }
    };
    match (side.on, clear) {
        (false, _) => format!("- no `{name}`: {why}."),
        (true, true) => format!(
            "- `{name}({primary})`: no {secondary} is in region {k} of the {primary} ({why})."
        ),
        (true, false) => format!(
            "- `{name}({secondary})`: the {secondary} is in region {k} of no {primary} ({why})."
        ),
    }
}

/// An English plural of a type name: `es` after a hiss, else `s`.
/// "looks the same half turned", "… after each of 3 turns".
fn plural_turns(count: usize) -> String {
    match count {
        2 => "looks the same half turned".to_string(),
        count => format!("looks the same after each of {} turns", count - 1),
    }
}

fn plural(type_name: &str) -> String {
    let hiss = ["s", "x", "z", "ch", "sh"].iter().any(|end| type_name.ends_with(end));
    format!("{type_name}{}", if hiss { "es" } else { "s" })
}

fn region_row(out: &mut String, region: &Region) {
    let summary: &RegionSummary = &region.summary;
    let position = summary.representative.translation.vector;
    let (roll, pitch, yaw) = summary.representative.rotation.euler_angles();
    let _ = writeln!(
        out,
        "| `{}` | {} | {} | {} | {}; {} {} {} | {} | {} | {} | {} |",
        region.relation,
        summary.g,
        triple(summary.centre),
        triple(summary.spread),
        triple([position.x, position.y, position.z]),
        rounded(roll.to_degrees(), 0),
        rounded(pitch.to_degrees(), 0),
        rounded(yaw.to_degrees(), 0),
        summary.cells.cell_count(),
        region.model.component_count(),
        summary.demonstrations,
        summary.time_steps
    );
}

fn triple(values: [f64; 3]) -> String {
    format!("({}, {}, {})", rounded(values[0], 3), rounded(values[1], 3), rounded(values[2], 3))
}

/// Rounds first, so values that round to zero print as `0` and not `-0`.
fn rounded(value: f64, decimals: i32) -> String {
    let scale = 10f64.powi(decimals);
    let value = (value * scale).round() / scale + 0.0;
    format!("{value:.prec$}", prec = decimals as usize)
}

fn action_section(out: &mut String, action: &Action) {
    let _ = writeln!(out, "### `{}`\n", action.name);
    let parameters: Vec<String> =
        action.parameters.iter().map(|p| format!("`{} - {}`", p.name, p.type_name)).collect();
    let _ = writeln!(out, "- parameters: {}", parameters.join(", "));
    let list = |atoms: &[crate::actions::LiftedAtom]| -> String {
        if atoms.is_empty() {
            "none".to_string()
        } else {
            atoms.iter().map(|atom| format!("`{atom}`")).collect::<Vec<_>>().join(", ")
        }
    };
    let _ = writeln!(out, "- preconditions: {}", list(&action.preconditions));
    if !action.negative_preconditions.is_empty() {
        let absent: Vec<String> =
            action.negative_preconditions.iter().map(|atom| format!("`(not {atom})`")).collect();
        let _ = writeln!(out, "- negated preconditions: {}", absent.join(", "));
    }
    let _ = writeln!(out, "- adds: {}", list(&action.add));
    let _ = writeln!(out, "- deletes: {}", list(&action.delete));
    let listed: Vec<String> = action
        .transitions
        .iter()
        .take(LISTED_TRANSITIONS)
        .map(|t| format!("{}@{}", t.demonstration, t.step))
        .collect();
    let more = action.transitions.len().saturating_sub(LISTED_TRANSITIONS);
    let tail = if more > 0 { format!(" and {more} more") } else { String::new() };
    let _ = writeln!(
        out,
        "- induced from {} transitions ({} distinct): {}{tail}\n",
        action.transitions.len(),
        action.distinct_transitions,
        listed.join(", ")
    );
}

/// `1 place`, `2 places`.
fn counted(count: usize, noun: &str) -> String {
    match count {
        1 => format!("1 {noun}"),
        count => format!("{count} {noun}s"),
    }
}
