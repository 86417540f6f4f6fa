//! Whether a pair's relative poses are compared up to its shapes' symmetries, decided from the
//! demonstrations (`symmetry auto`).
//!
//! Comparing up to a symmetry folds the relative poses onto one place of each orbit. That pays
//! where the demonstrations show one rest at several places of an orbit (a Jenga block across
//! another at a corner or at the opposite one, from either block's frame): folded, they are one
//! place, learned from all of their demonstrations together. It costs where folding brings two
//! different rests within millimetres of each other: a Keva plank's frame sits on its bottom face,
//! so a lintel resting on a leg whose frame faces it and one on a leg facing away fold to poses
//! 7 mm apart, and the groups that kept them apart are no longer separated from their
//! neighbours, so neither is found. And it brings nothing where every place is its own image (a
//! can anywhere on a square box's floor).
//!
//! So the places are found both ways, and the folded ones are taken when no place found as
//! recorded is lost by folding (more than half of its keyframes, taken to their representatives,
//! lie in folded places of the same held flag), and folding merges places, tells apart rests the
//! recorded poses joined into one place (its keyframes land in several folded places), finds a
//! place the recorded poses were too sparse to show (a folded place holds none of their
//! keyframes), or covers a place's orbit where the recorded places do not: forty Keva
//! demonstrations show a plank crossed over another at one corner, and as recorded the region
//! there says nothing of the same rest at the opposite corner, which a structure may ask for.
//! Places are compared by their keyframes, not by their centres: the centre of a place that
//! joins two rests lies between them, in neither.

use std::collections::BTreeSet;

use crate::demo::Pose;
use crate::selection::Group;

/// How the folded places compare with those found as recorded.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SymmetryChoice {
    /// Whether the folded places were taken.
    pub folded: bool,
    /// Places found as recorded.
    pub places_as_recorded: usize,
    /// Places found folded.
    pub places_folded: usize,
    /// Keyframes in places, as recorded.
    pub keyframes_as_recorded: usize,
    /// Keyframes in places, folded.
    pub keyframes_folded: usize,
    /// The centre (its representative, m) of the first place found as recorded that no folded
    /// place holds, if any.
    pub lost: Option<[f64; 3]>,
    /// The first position (m, as recorded) of an orbit member of a place found as recorded that
    /// no place found as recorded holds, if any: a rest the recorded places know at one place of
    /// its orbit and not at another.
    pub uncovered: Option<[f64; 3]>,
}

/// Compares the places (a selection's groups) found as recorded and folded; `representative`
/// takes a relative pose to its orbit's representative position, and `orbit` a position (with
/// the identity orientation) to the positions of its orbit's members. Without a selection on
/// either side (every setting pinned) nothing is folded.
pub fn choose(
    as_recorded: Option<&[Group]>,
    folded: Option<&[Group]>,
    representative: impl Fn(&Pose) -> [f64; 3],
    orbit: impl Fn([f64; 3]) -> Vec<[f64; 3]>,
) -> SymmetryChoice {
    let (Some(as_recorded), Some(folded)) = (as_recorded, folded) else {
        return SymmetryChoice::default();
    };
    let keyframes = |groups: &[Group]| groups.iter().map(Group::keyframes).sum::<usize>();
    // Where folding takes each keyframe of each place found as recorded: the first folded place
    // of the same held flag that holds its representative, if any.
    let landings: Vec<Vec<Option<usize>>> = as_recorded
        .iter()
        .map(|place| {
            let landing = |pose: &Pose| {
                let position = representative(pose);
                folded.iter().position(|group| group.g == place.g && holds(group, position))
            };
            place.poses.iter().map(landing).collect()
        })
        .collect();
    // A place is lost when folding leaves at least half of its keyframes in no place. Its centre
    // alone would call a place that joins two rests lost where folding keeps both, since the
    // centre lies between them.
    let lost = as_recorded.iter().zip(&landings).find_map(|(place, landing)| {
        let [x, y, z] = place.centre;
        let kept = landing.iter().flatten().count();
        (2 * kept <= landing.len()).then(|| representative(&Pose::translation(x, y, z)))
    });
    let (places_as_recorded, places_folded) = (as_recorded.len(), folded.len());
    let (keyframes_as_recorded, keyframes_folded) = (keyframes(as_recorded), keyframes(folded));
    // Folding tells apart rests the recorded poses joined into one place when that place's
    // keyframes land in several folded places; it finds a rest they were too sparse to show when
    // a folded place holds none of their keyframes (a few keyframes more or fewer in the same
    // places are neither).
    let splits =
        landings.iter().any(|landing| landing.iter().flatten().collect::<BTreeSet<_>>().len() > 1);
    let landed: BTreeSet<usize> = landings.iter().flatten().flatten().copied().collect();
    let found = landed.len() < places_folded;
    let uncovered = as_recorded.iter().find_map(|place| {
        orbit(place.centre).into_iter().find(|member| {
            !as_recorded.iter().any(|other| other.g == place.g && holds(other, *member))
        })
    });
    let pays = places_folded < places_as_recorded || splits || found || uncovered.is_some();
    SymmetryChoice {
        folded: lost.is_none() && pays && places_folded > 0,
        places_as_recorded,
        places_folded,
        keyframes_as_recorded,
        keyframes_folded,
        lost,
        uncovered,
    }
}

/// Whether `centre` lies in the group's box of keyframes, widened by its tolerance.
fn holds(group: &Group, centre: [f64; 3]) -> bool {
    (0..3).all(|axis| {
        centre[axis] >= group.low[axis] - group.tolerance
            && centre[axis] <= group.high[axis] + group.tolerance
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn group(g: u8, centre: [f64; 3], keyframes: usize) -> Group {
        Group {
            g,
            demonstrations: keyframes,
            scale: 0.001,
            centre,
            low: centre.map(|c| c - 0.002),
            high: centre.map(|c| c + 0.002),
            share: 1.0,
            tolerance: 0.002,
            poses: vec![Pose::translation(centre[0], centre[1], centre[2]); keyframes],
        }
    }

    /// The half turn about z: the representative has the larger x.
    fn half_turn(pose: &Pose) -> [f64; 3] {
        let [x, y, z]: [f64; 3] = pose.translation.vector.into();
        if x >= 0.0 { [x, y, z] } else { [-x, -y, z] }
    }

    /// The positions of the half turn's orbit.
    fn half_turn_orbit(position: [f64; 3]) -> Vec<[f64; 3]> {
        vec![position, [-position[0], -position[1], position[2]]]
    }

    #[test]
    fn places_at_both_ends_of_an_orbit_fold_into_one() {
        let recorded = [group(0, [0.05, 0.05, 0.03], 20), group(0, [-0.05, -0.05, 0.03], 18)];
        let folded = [group(0, [0.05, 0.05, 0.03], 38)];
        let choice = choose(Some(&recorded[..]), Some(&folded[..]), half_turn, half_turn_orbit);
        assert!(choice.folded, "{choice:?}");
        assert_eq!((choice.places_as_recorded, choice.places_folded), (2, 1));
    }

    #[test]
    fn a_place_lost_by_folding_keeps_the_poses_as_recorded() {
        let recorded = [
            group(0, [0.05, 0.05, 0.03], 20),
            group(0, [-0.05, -0.05, 0.03], 18),
            group(0, [0.06, 0.0, 0.04], 8),
        ];
        // The third place's neighbour after folding swallowed it: no folded group holds it.
        let folded = [group(0, [0.05, 0.05, 0.03], 38)];
        let choice = choose(Some(&recorded[..]), Some(&folded[..]), half_turn, half_turn_orbit);
        assert!(!choice.folded);
        assert_eq!(choice.lost, Some([0.06, 0.0, 0.04]));
        // A place of another held flag does not hold it either.
        let other_flag = [group(0, [0.05, 0.05, 0.03], 38), group(1, [0.06, 0.0, 0.04], 8)];
        assert!(
            !choose(Some(&recorded[..]), Some(&other_flag[..]), half_turn, half_turn_orbit).folded
        );
    }

    #[test]
    fn a_place_joining_two_rests_that_folding_keeps_is_not_lost() {
        // As recorded, a plank crossed over another and one crossed under it, each too rare
        // alone, are joined into one place whose centre lies between them; folded, each is a place
        // of its own (the folded places hold the representatives of the recorded ones at the
        // opposite corner too).
        let above = [0.045, 0.045, 0.016];
        let below = [-0.045, -0.045, -0.016];
        let joined = Group {
            poses: [above, below]
                .iter()
                .flat_map(|&[x, y, z]| vec![Pose::translation(x, y, z); 4])
                .collect(),
            low: below.map(|c| c - 0.002),
            high: above.map(|c| c + 0.002),
            ..group(0, [0.0, 0.0, 0.0], 8)
        };
        let folded = [group(0, above, 6), group(0, [0.045, 0.045, -0.016], 6)];
        let choice =
            choose(Some(&[joined.clone()][..]), Some(&folded[..]), half_turn, half_turn_orbit);
        assert_eq!(choice.lost, None, "{choice:?}");
        assert!(choice.folded, "{choice:?}");
        // With only one of the two rests folded into a place, half of the keyframes are in none.
        let choice = choose(Some(&[joined][..]), Some(&folded[..1]), half_turn, half_turn_orbit);
        assert_eq!(choice.lost, Some([0.0, 0.0, 0.0]));
        assert!(!choice.folded);
    }

    #[test]
    fn folding_that_changes_nothing_is_not_taken() {
        // A can anywhere on a box's floor: one place either way, the same keyframes in it.
        let floor = |centre: [f64; 3], low_x: f64| Group {
            low: [low_x, -0.04, 0.001],
            high: [0.04, 0.04, 0.001],
            ..group(0, centre, 40)
        };
        let recorded = [floor([0.0, 0.0, 0.001], -0.04)];
        let folded = [floor([0.02, 0.0, 0.001], 0.0)];
        // A few keyframes more in the same place are no gain either.
        let more = vec![Pose::translation(0.02, 0.0, 0.001); 41];
        let denser = [Group { poses: more, ..floor([0.02, 0.0, 0.001], 0.0) }];
        assert!(!choose(Some(&recorded[..]), Some(&denser[..]), half_turn, half_turn_orbit).folded);
        let choice = choose(Some(&recorded[..]), Some(&folded[..]), half_turn, half_turn_orbit);
        assert!(!choice.folded && choice.lost.is_none(), "{choice:?}");
        // Nor without a selection (every setting pinned).
        assert!(!choose(None, Some(&folded[..]), half_turn, half_turn_orbit).folded);
    }

    #[test]
    fn a_place_whose_keyframes_all_fold_into_one_place_is_neither_lost_nor_new() {
        // A can anywhere on a table, seen at four spots around its centre: folded by the half
        // turn, every keyframe lands on one side, in one place whose box does not reach the
        // recorded place's centre. Judged by that centre the place was lost, and the folded place
        // a rest the recorded poses never showed; judged by the keyframes it is the same place.
        let spots = [[0.03, 0.03], [-0.03, -0.03], [0.03, -0.03], [-0.03, 0.03]];
        let table = Group {
            poses: spots.iter().map(|&[x, y]| Pose::translation(x, y, 0.001)).collect(),
            low: [-0.032, -0.032, 0.0],
            high: [0.032, 0.032, 0.002],
            ..group(0, [0.0, 0.0, 0.001], 4)
        };
        let folded = Group {
            low: [0.028, -0.032, 0.0],
            high: [0.032, 0.032, 0.002],
            ..group(0, [0.03, 0.0, 0.001], 4)
        };
        let choice = choose(Some(&[table][..]), Some(&[folded][..]), half_turn, half_turn_orbit);
        assert_eq!(choice.lost, None, "{choice:?}");
        assert!(!choice.folded, "nothing gained: {choice:?}");
    }

    #[test]
    fn folding_that_finds_rests_too_sparse_to_be_places_as_recorded_is_taken() {
        let recorded = [group(0, [0.05, 0.05, 0.03], 6)];
        let folded = [group(0, [0.05, 0.05, 0.03], 12), group(0, [0.05, -0.05, 0.03], 6)];
        assert!(choose(Some(&recorded[..]), Some(&folded[..]), half_turn, half_turn_orbit).folded);
    }

    #[test]
    fn a_rest_known_at_one_place_of_its_orbit_is_folded() {
        // Forty demonstrations show a plank crossed over another at one corner only: as recorded,
        // nothing holds the same rest at the opposite corner; folded, the one place holds both.
        let recorded = [group(0, [0.045, 0.045, 0.008], 8)];
        let folded = [group(0, [0.045, 0.045, 0.008], 10)];
        let choice = choose(Some(&recorded[..]), Some(&folded[..]), half_turn, half_turn_orbit);
        assert!(choice.folded, "{choice:?}");
        assert_eq!(choice.uncovered, Some([-0.045, -0.045, 0.008]));
        // With the opposite corner recorded too, its own place, the places cover their orbits.
        let both = [group(0, [0.045, 0.045, 0.008], 8), group(0, [-0.045, -0.045, 0.008], 8)];
        let choice = choose(Some(&both[..]), Some(&folded[..]), half_turn, half_turn_orbit);
        assert_eq!(choice.uncovered, None);
        assert!(choice.folded, "two places in one: {choice:?}");
    }
}
