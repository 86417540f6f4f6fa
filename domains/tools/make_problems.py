"""Generates the bundled test problems of the Packing, Café, Dinner, Keva and Jenga specs.

Run `python3 domains/tools/make_problems.py packing` (or `cafe`, `dinner`, `keva`, `jenga`) and paste the printed
problem blocks into domains/packing/packing.lamp (domains/cafe/cafe.lamp,
domains/dinner/dinner.lamp) in place of the old ones;
`cafe-layouts` prints the Café problems on the other furniture layouts, which follow the `cafe`
ones in domains/cafe/cafe.lamp.
The output is deterministic: each mode has a fixed seed, and every layout is checked against
the rules below after rounding, so the printed numbers are the checked ones.

Packing (12 problems pack4_01 … pack4_12): the 0.9 m × 0.9 m table, the open box (outer
0.17 m × 0.17 m) somewhere on it with some yaw, four cans (radius 0.0325 m) standing on the
table at z = 0.001 m with random yaw, and the gripper above the table; the goal is all four cans
in the box. Cans keep 2 cm from each other, from the box and from the table's edge.
pack4_01 is the original hand-written problem, kept as it was (it satisfies the same rules).

Café, `cafe` (12 problems with 2, 2, 3, 4, 4, 6, 8, 8, 10, 16, 17, 18 cans): one furniture
layout (four tables, one counter, every top a 0.9 m × 0.9 m `surface`, tables 0.73 m and the
counter 0.9 m high, all at least 0.8 m apart so the Fetch base, radius 0.28 m, drives between
them), cans (radius 0.045 m) on the surfaces at surface z + 0.001 m, 3 cm apart and at least
5 cm from a surface's edge; every can gets a goal surface and at least half of them move.
The Fetch starts at the floor origin, tucked, more than 1 m from every piece of furniture.

Café, `cafe-layouts` (9 problems cafe_l<layout>_<cans>_<k>): three more layouts drawn from their
own seed, layout 2 with four tables and a counter (4, 12 and 24 cans), layout 3 with four tables
and two counters (8, 18 and 30 cans), layout 4 with three tables and a counter (6, 12 and 18
cans). Every surface has a random position and a random yaw in whole degrees, mostly not a
multiple of 90°; the same rules hold, checked with exact rotated-rectangle geometry: tops at
least 0.8 m apart, the origin at least 1 m from every top, every corner of a top within 5 m of
the origin along each axis. Cans are placed in a surface's frame as above and turned with its yaw.

Dinner, `dinner` (12 problems set_table_<n>): a random layout per problem (one or two dining
tables, side tables and a counter, the Café rules), place settings on random edges of the dining
tables (a bowl near the edge, a glass behind it and to the right; a third glass of a setting
beside the bowl), each target 1 mm above the top and at least 3 cm from the others, and the
objects on the other tops as Café cans are; every goal an AtGoal within 2 cm at any yaw.

Keva, `keva` (12 structures and problems named <structure>_<planks>): planks 0.117 m × 0.023 m ×
0.007 m, frame at the centre of the bottom face. A pi is two planks standing upright (long axis
vertical, 23 mm wide across the lintel) 7.75 cm apart and a third lying flat across their tops;
structures are pis (side by side, stacked, in a ring), log-cabin towers of flat planks (two per
layer, each layer turned 90°) and a small house. Every plank rests 1 mm (RESTING_GAP) above the
table or the planks below it. The table stands at x = 0.17 m, clear of the YuMi's body. The
anchor `area1` is a `droparea`, an area drawn on the table top
(its box lies in the table, so the anchor frame is the table's top face). The planks start lying
flat on the table in a grid (0.13 m along a plank, 0.065 m across: lying flat side by side, planks
are in no learned plank–plank region, and the fingers straddling one clear its neighbours) where the
YuMi's left arm takes a top grasp (within 0.55 m of (-0.46, 0.1), measured with lamp's IK), the
spots nearest the YuMi's shoulder first, none within 0.12 m of a plank of the structure (0.10 m of
the ring, whose anchor is turned 30° so that the YuMi reaches every leg: KEVA_OWN_ANCHORS).

Jenga, `jenga` (14 towers tower_<blocks>, 2 … 18 blocks, then 24 and 30): blocks 0.1524 m ×
0.0508 m × 0.03048 m, frame at the centre; layers of two blocks at the outer positions (±0.0508 m
across, a gap in the middle), each layer turned 90° from the one below, 1 mm between layers and
above the table; an odd count leaves one block on the top layer, at the + position. Anchors
(`build_area`, drawn on the table top) differ per problem, some turned; blocks start lying flat
on the table, long axis toward the Fetch, on a grid 0.2 m along it and 0.1 m across (the open
fingers keep 2 cm from a neighbour; every block is outside the others' block–block bins, ±0.075 m),
the spots nearest the Fetch's shoulder first, none within 4 cm or the bins of a block of the
bottom three layers of the tower. The table holds 27 spots, at least 21 beside any tower; the
30-block tower also uses two side tables beside the Fetch, with six spots each. Every spot is
within the arm's reach (domains/demonstrators/tests/jenga.rs).

The bundled tests (tests/domains.rs) check the result with lamp's own collision checker, and
every structure at its problem's anchor with the resting rule.
"""

import math
import random
import sys

# --- Packing ---------------------------------------------------------------------------------

TABLE_HALF = 0.45
BOX_HALF = 0.085  # outer half side of the box (walls at ±0.08, 1 cm thick)
CAN_RADIUS = 0.0325
PACK_CLEARANCE = 0.02

ORIGINAL_PACK4_01 = {
    "box": (0.25, 0.15, 30),
    "cans": [(-0.25, -0.20, 0), (-0.10, -0.25, 45), (0.05, -0.30, 0), (-0.30, 0.05, 90)],
}


def rectangle_distance(px, py, cx, cy, yaw_deg, hx, hy):
    """Distance from point (px, py) to a rectangle of half sizes (hx, hy) centred at (cx, cy),
    yawed by `yaw_deg` degrees; 0 inside."""
    yaw = math.radians(yaw_deg)
    dx, dy = px - cx, py - cy
    lx = math.cos(yaw) * dx + math.sin(yaw) * dy
    ly = -math.sin(yaw) * dx + math.cos(yaw) * dy
    ox, oy = max(abs(lx) - hx, 0.0), max(abs(ly) - hy, 0.0)
    return math.hypot(ox, oy)


def packing_ok(layout):
    bx, by, byaw = layout["box"]
    # The box lies on the table: its farthest corner stays inside the top.
    reach = BOX_HALF * math.sqrt(2)
    if max(abs(bx), abs(by)) + reach > TABLE_HALF - PACK_CLEARANCE:
        return False
    cans = layout["cans"]
    for i, (x, y, _) in enumerate(cans):
        if max(abs(x), abs(y)) + CAN_RADIUS > TABLE_HALF - PACK_CLEARANCE:
            return False
        if rectangle_distance(x, y, bx, by, byaw, BOX_HALF, BOX_HALF) < CAN_RADIUS + PACK_CLEARANCE:
            return False
        for (x2, y2, _) in cans[:i]:
            if math.hypot(x - x2, y - y2) < 2 * CAN_RADIUS + PACK_CLEARANCE:
                return False
    return True


def packing_layouts():
    rng = random.Random(20251)
    layouts = [ORIGINAL_PACK4_01]
    assert packing_ok(ORIGINAL_PACK4_01)
    limit_box = TABLE_HALF - PACK_CLEARANCE - BOX_HALF * math.sqrt(2)
    limit_can = TABLE_HALF - PACK_CLEARANCE - CAN_RADIUS
    while len(layouts) < 12:
        box = (round(rng.uniform(-limit_box, limit_box), 2),
               round(rng.uniform(-limit_box, limit_box), 2),
               rng.randrange(0, 90))
        # Different layouts: the box is not where an earlier problem has it.
        if any(math.hypot(box[0] - l["box"][0], box[1] - l["box"][1]) < 0.08 for l in layouts):
            continue
        cans = []
        tries = 0
        while len(cans) < 4 and tries < 1000:
            tries += 1
            can = (round(rng.uniform(-limit_can, limit_can), 2),
                   round(rng.uniform(-limit_can, limit_can), 2),
                   rng.randrange(0, 360))
            if packing_ok({"box": box, "cans": cans + [can]}):
                cans.append(can)
        if len(cans) == 4:
            layouts.append({"box": box, "cans": cans})
    return layouts


def fmt(value):
    """A number with at most three decimals, trailing zeros dropped."""
    text = f"{value:.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("", "-0") else text


def rpy(yaw):
    return f" rpy (0, 0, {yaw}) deg" if yaw else ""


# Problems whose robot starts away from where the others start, facing another way: solving must
# not depend on the start (a mobile base anywhere on the free floor, the free gripper anywhere
# above the table). Each start was checked free of the problem's furniture.
STARTS = {
    "pack4_10": "(0.3, -0.3, 0.5) m rpy (180, 0, 120) deg",
    "pack4_11": "(-0.35, 0.3, 0.6) m rpy (180, 0, -75) deg",
    "pack4_12": "(0.1, 0.35, 0.4) m rpy (180, 0, 200) deg",
    "cafe4_02": "(2.5, -2.4, 0) m rpy (0, 0, 167) deg",
    "cafe8_02": "(-1, 1.2, 0) m rpy (0, 0, -100) deg",
    "set_table_2_02": "(2.5, -1.25, 0) m rpy (0, 0, 167) deg",
    "set_table_4_02": "(-1.5, -1, 0) m rpy (0, 0, -100) deg",
    "set_table_6_02": "(0.5, -2, 0) m rpy (0, 0, 80) deg",
    "set_table_8_02": "(-2, 0.5, 0) m rpy (0, 0, 20) deg",
}
PACKING_START = "(0, 0, 0.45) m rpy (180, 0, 0) deg"
FETCH_START = "(0, 0, 0) m"


def start_note(name, robot):
    """The sentence a problem's comment gets when its robot starts elsewhere."""
    if name not in STARTS:
        return ""
    if robot == "gripper":
        return " The gripper starts away from the table's centre, turned."
    return " The robot starts away from the origin, facing another way."


def print_packing():
    for index, layout in enumerate(packing_layouts(), start=1):
        bx, by, byaw = layout["box"]
        gap = min(
            math.hypot(a[0] - b[0], a[1] - b[1]) - 2 * CAN_RADIUS
            for i, a in enumerate(layout["cans"]) for b in layout["cans"][:i]
        )
        note = "the original problem" if index == 1 else "generated"
        name = f"pack4_{index:02d}"
        print(f"// {name}: box at ({fmt(bx)}, {fmt(by)}) yawed {byaw} deg; "
              f"closest cans {gap * 100:.0f} cm apart ({note})." + start_note(name, "gripper"))
        print(f"problem pack4_{index:02d} {{")
        print("  scene {")
        print("    table table1 at (0, 0, 0) m")
        print(f"    surface box1 at ({fmt(bx)}, {fmt(by)}, 0) m{rpy(byaw)}")
        for k, (x, y, yaw) in enumerate(layout["cans"], start=1):
            print(f"    can can{k} at ({fmt(x)}, {fmt(y)}, 0.001) m{rpy(yaw)}")
        print(f"    robot gripper at {STARTS.get(name, PACKING_START)}")
        print("  }")
        print("  goal {")
        for k in range(1, 5):
            print(f"    in_box(can{k}, box1)")
        print("  }")
        print("}")
        print()


# --- Café ------------------------------------------------------------------------------------

CAFE_CAN_RADIUS = 0.045
CAFE_CAN_GAP = 0.03
CAFE_EDGE = 0.05
FURNITURE_GAP = 0.8  # Fetch base diameter 0.56 m plus room to turn
ROBOT_CLEARANCE = 1.0
# Every corner of a generated layout's tops stays this close to the floor origin (the floor is
# 20 m × 20 m; a compact café keeps the drives short).
LAYOUT_BOUND = 5.0
TABLE_Z = 0.73
COUNTER_Z = 0.9
TOP_HALF = 0.45

# name, the world-type body under the top, x, y, top z, yaw (deg), half sizes of the top in the
# surface frame. Every top is a `surface` (one type, as in the paper's CafeWorld, so that "on a
# surface" and "standing at a surface" are one relation each); what holds it up is scenery of a
# `static world` type at the same pose, named after it.
SURFACES = [
    ("table1", "table_leg", 2.0, -1.0, 0.73, 0, 0.45, 0.45),
    ("table2", "table_leg", 4.0, 1.5, 0.73, 90, 0.45, 0.45),
    ("table3", "table_leg", -2.0, -1.5, 0.73, 0, 0.45, 0.45),
    ("table4", "table_leg", 2.5, 3.2, 0.73, 0, 0.45, 0.45),
    ("counter1", "counter_cabinet", 0.5, 2.5, 0.9, 0, 0.45, 0.45),
]
STAND_SUFFIX = {"table_leg": "leg", "counter_cabinet": "cabinet"}

CAFE_COUNTS = [2, 2, 3, 4, 4, 6, 8, 8, 10, 16, 17, 18]

# The other layouts (`cafe-layouts`): layout number, tables, counters, and the can counts of its
# problems. Together they cover 4 to 30 cans on 4 to 6 surfaces.
OTHER_LAYOUTS = [
    (2, 4, 1, [4, 12, 24]),
    (3, 4, 2, [8, 18, 30]),
    (4, 3, 1, [6, 12, 18]),
]


def corners(surface):
    """The four world corners of a surface's top, counter-clockwise."""
    _, _, x, y, _, yaw, hx, hy = surface
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    return [(x + c * lx - s * ly, y + s * lx + c * ly)
            for lx, ly in ((hx, hy), (-hx, hy), (-hx, -hy), (hx, -hy))]


def overlap(a, b):
    """Whether two convex polygons (lists of corners) overlap: no edge normal separates them."""
    for poly in (a, b):
        for (x1, y1), (x2, y2) in zip(poly, poly[1:] + poly[:1]):
            nx, ny = y1 - y2, x2 - x1
            pa = [nx * px + ny * py for px, py in a]
            pb = [nx * px + ny * py for px, py in b]
            if max(pa) < min(pb) or max(pb) < min(pa):
                return False
    return True


def segment_distance(px, py, a, b):
    """Distance from point (px, py) to the segment from a to b."""
    (ax, ay), (bx, by) = a, b
    ex, ey = bx - ax, by - ay
    t = max(0.0, min(1.0, ((px - ax) * ex + (py - ay) * ey) / (ex * ex + ey * ey)))
    return math.hypot(px - ax - t * ex, py - ay - t * ey)


def footprint_distance(a, b):
    """Exact distance between two surfaces' tops seen from above, at any yaw; 0 if they overlap.
    Two disjoint convex polygons are closest at a corner of one and an edge of the other."""
    pa, pb = corners(a), corners(b)
    if overlap(pa, pb):
        return 0.0
    return min(
        segment_distance(px, py, q1, q2)
        for first, second in ((pa, pb), (pb, pa))
        for px, py in first
        for q1, q2 in zip(second, second[1:] + second[:1])
    )


def furniture_ok(surfaces):
    for i, a in enumerate(surfaces):
        _, _, x, y, _, yaw, hx, hy = a
        # The robot at the origin (radius 0.28 m, tucked arm inside) keeps a metre away.
        if rectangle_distance(0.0, 0.0, x, y, yaw, hx, hy) < ROBOT_CLEARANCE:
            return False
        if any(max(abs(cx), abs(cy)) > LAYOUT_BOUND for cx, cy in corners(a)):
            return False
        for b in surfaces[:i]:
            if footprint_distance(a, b) < FURNITURE_GAP:
                return False
    return True


def make_layout(rng, tables, counters):
    """A random layout: `tables` tables then `counters` counters, each at any yaw (whole
    degrees), drawn again until every rule of `furniture_ok` holds."""
    kinds = [("table", "table_leg", TABLE_Z)] * tables
    kinds += [("counter", "counter_cabinet", COUNTER_Z)] * counters
    limit = LAYOUT_BOUND - TOP_HALF
    while True:
        surfaces = []
        numbers = {}
        for stem, stand, z in kinds:
            numbers[stem] = numbers.get(stem, 0) + 1
            surfaces.append((f"{stem}{numbers[stem]}", stand,
                             round(rng.uniform(-limit, limit), 2),
                             round(rng.uniform(-limit, limit), 2),
                             z, rng.randrange(0, 360), TOP_HALF, TOP_HALF))
        if furniture_ok(surfaces):
            return surfaces


def to_world(surface, lx, ly):
    _, _, x, y, z, yaw, _, _ = surface
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
    return x + c * lx - s * ly, y + s * lx + c * ly, z + 0.001


def inside(surface, x, y):
    """Whether a can at world (x, y) stands on the surface, its edge CAFE_EDGE from the top's
    edges (checked on the rounded numbers that are printed)."""
    _, _, sx, sy, _, yaw, hx, hy = surface
    return rectangle_distance(x, y, sx, sy, yaw, hx - CAFE_EDGE - CAFE_CAN_RADIUS,
                              hy - CAFE_EDGE - CAFE_CAN_RADIUS) == 0.0


def place_cans(rng, surfaces, count):
    """Cans on random surfaces; returns (surface index, world x, y, z, yaw) per can."""
    cans = []
    while len(cans) < count:
        index = rng.randrange(len(surfaces))
        surface = surfaces[index]
        hx = surface[6] - CAFE_EDGE - CAFE_CAN_RADIUS
        hy = surface[7] - CAFE_EDGE - CAFE_CAN_RADIUS
        lx, ly = round(rng.uniform(-hx, hx), 2), round(rng.uniform(-hy, hy), 2)
        if abs(lx) > hx or abs(ly) > hy:
            continue
        x, y, z = to_world(surface, lx, ly)
        x, y = round(x, 3), round(y, 3)
        if not inside(surface, x, y):
            continue
        if any(math.hypot(x - c[1], y - c[2]) < 2 * CAFE_CAN_RADIUS + CAFE_CAN_GAP for c in cans):
            continue
        cans.append((index, x, y, z, rng.randrange(0, 360)))
    return cans


def goals(rng, surfaces, cans):
    """A goal surface per can; at least half of the cans move to another surface."""
    count = len(cans)
    movers = set(rng.sample(range(count), (count + 1) // 2))
    result = []
    for k, can in enumerate(cans):
        if k in movers:
            choices = [i for i in range(len(surfaces)) if i != can[0]]
        else:
            choices = list(range(len(surfaces)))
        result.append(rng.choice(choices))
    return result


def print_furniture(surfaces):
    """The floor, then every top with what holds it up, as scene lines."""
    print("    floor floor1 at (0, 0, 0) m")
    for surface in surfaces:
        sname, stand, x, y, z, yaw, _, _ = surface
        at = f"at ({fmt(x)}, {fmt(y)}, {fmt(z)}) m{rpy(yaw)}"
        print(f"    surface {sname} {at}")
        print(f"    {stand} {sname}_{STAND_SUFFIX[stand]} {at}")


def print_cafe_problem(rng, surfaces, name, count):
    cans = place_cans(rng, surfaces, count)
    targets = goals(rng, surfaces, cans)
    moving = sum(1 for can, goal in zip(cans, targets) if goal != can[0])
    starts = [sum(1 for c in cans if c[0] == i) for i in range(len(surfaces))]
    where = ", ".join(f"{surfaces[i][0]} {n}" for i, n in enumerate(starts) if n)
    print(f"// {name}: {count} cans ({where}); {moving} move to another surface."
          + start_note(name, "fetch"))
    print(f"problem {name} {{")
    print("  scene {")
    print_furniture(surfaces)
    for k, (_, x, y, z, yaw) in enumerate(cans, start=1):
        print(f"    can can{k} at ({fmt(x)}, {fmt(y)}, {fmt(z)}) m{rpy(yaw)}")
    print(f"    robot fetch at {STARTS.get(name, FETCH_START)} config tuck")
    print("  }")
    print("  goal {")
    for k, goal in enumerate(targets, start=1):
        print(f"    on(can{k}, {surfaces[goal][0]})")
    print("  }")
    print("}")
    print()


def print_cafe():
    assert furniture_ok(SURFACES)
    rng = random.Random(20252)
    seen = {}
    for count in CAFE_COUNTS:
        seen[count] = seen.get(count, 0) + 1
        print_cafe_problem(rng, SURFACES, f"cafe{count}_{seen[count]:02d}", count)


def print_cafe_layouts():
    rng = random.Random(20253)
    for number, tables, counters, counts in OTHER_LAYOUTS:
        surfaces = make_layout(rng, tables, counters)
        print(f"// Layout {number}: {len(surfaces)} surfaces.")
        for sname, _, x, y, z, yaw, _, _ in surfaces:
            print(f"//   {sname} at ({fmt(x)}, {fmt(y)}) m, {fmt(z)} m high, yawed {yaw} deg.")
        print()
        seen = {}
        for count in counts:
            seen[count] = seen.get(count, 0) + 1
            name = f"cafe_l{number}_{count}_{seen[count]:02d}"
            print_cafe_problem(rng, surfaces, name, count)


# --- Dinner -----------------------------------------------------------------------------------

GLASS_RADIUS = 0.0425
BOWL_RADIUS = 0.048
# A place setting at one edge of a dining table, in the frame of that edge (y towards the edge
# from the table's centre is -y): the bowl near the edge, the glass behind it and to the right,
# 6.6 cm apart, so that a glass put down first is reached past nothing, and one put down after
# the bowl is reached past the bowl.
SETTING_BOWL = (0.0, -0.28)
SETTING_GLASS = (0.10, -0.16)
# A second glass of a setting, beside the bowl on the other side, clear of the next edge's
# setting.
EXTRA_GLASS = (-0.13, -0.28)
# (problem name, dining tables, other tables, counters, settings, extra glasses on the side)
DINNER_PROBLEMS = [
    ("set_table_2", 1, 1, 1, 1, 0),
    ("set_table_2_02", 1, 2, 1, 1, 0),
    ("set_table_3", 1, 1, 1, 1, 1),
    ("set_table_4", 1, 1, 1, 2, 0),
    ("set_table_4_02", 1, 2, 1, 2, 0),
    ("set_table_5", 1, 2, 1, 2, 1),
    ("set_table_6", 1, 1, 1, 3, 0),
    ("set_table_6_02", 2, 1, 1, 3, 0),
    ("set_table_7", 1, 2, 1, 3, 1),
    ("set_table_8", 1, 1, 1, 4, 0),
    ("set_table_8_02", 2, 1, 1, 4, 0),
    ("set_table_12", 2, 1, 1, 6, 0),
]


def dinner_goal_lines(rng, dining, settings, extra):
    """The targets: `settings` place settings on random free edges of the dining tables, then
    `extra` glasses at the free corner of a set edge; (kind, x, y, z) each."""
    edges = [(table, side) for table in dining for side in range(4)]
    rng.shuffle(edges)
    targets = []
    for table, side in edges[:settings]:
        for kind, (lx, ly) in (("bowl", SETTING_BOWL), ("glass", SETTING_GLASS)):
            angle = math.radians(90 * side)
            c, s = math.cos(angle), math.sin(angle)
            targets.append((kind,) + to_world(table, c * lx - s * ly, s * lx + c * ly))
    for table, side in edges[:extra]:
        angle = math.radians(90 * side)
        c, s = math.cos(angle), math.sin(angle)
        lx, ly = EXTRA_GLASS
        targets.append(("glass",) + to_world(table, c * lx - s * ly, s * lx + c * ly))
    for i, a in enumerate(targets):
        for b in targets[:i]:
            reach = radius_of(a[0]) + radius_of(b[0]) + CAFE_CAN_GAP
            assert math.hypot(a[1] - b[1], a[2] - b[2]) >= reach, (a, b)
    return targets


def radius_of(kind):
    return GLASS_RADIUS if kind == "glass" else BOWL_RADIUS


def place_objects(rng, surfaces, kinds):
    """Objects of `kinds` on random surfaces, at least 3 cm apart and 5 cm from the edges."""
    placed = []
    for kind in kinds:
        radius = radius_of(kind)
        while True:
            surface = surfaces[rng.randrange(len(surfaces))]
            h = surface[6] - CAFE_EDGE - radius
            lx, ly = round(rng.uniform(-h, h), 2), round(rng.uniform(-h, h), 2)
            x, y, z = to_world(surface, lx, ly)
            x, y = round(x, 3), round(y, 3)
            _, _, sx, sy, _, yaw, hx, hy = surface
            if rectangle_distance(x, y, sx, sy, yaw, hx - CAFE_EDGE - radius,
                                  hy - CAFE_EDGE - radius) > 0.0:
                continue
            if any(math.hypot(x - o[1], y - o[2]) < radius + o[4] + CAFE_CAN_GAP for o in placed):
                continue
            placed.append((kind, x, y, z, radius))
            break
    return placed


def print_dinner():
    rng = random.Random(20254)
    for name, dining_count, tables, counters, settings, extra in DINNER_PROBLEMS:
        surfaces = make_layout(rng, dining_count + tables, counters)
        dining = surfaces[:dining_count]
        for k, table in enumerate(dining, start=1):
            dining[k - 1] = (f"dining{k}",) + table[1:]
        surfaces = dining + surfaces[dining_count:]
        targets = dinner_goal_lines(rng, dining, settings, extra)
        objects = place_objects(rng, surfaces[dining_count:], [t[0] for t in targets])
        kinds = [t[0] for t in targets]
        print(f"// {name}: {kinds.count('glass')} glasses and {kinds.count('bowl')} bowls onto "
              f"{settings} place setting(s)" + (f" and {extra} extra glass(es)" if extra else "")
              + f" on {dining_count} dining table(s)." + start_note(name, "fetch"))
        print(f"problem {name} {{")
        print("  scene {")
        print_furniture(surfaces)
        numbers = {}
        names = []
        for kind, x, y, z, _ in objects:
            numbers[kind] = numbers.get(kind, 0) + 1
            names.append(f"{kind}{numbers[kind]}")
            print(f"    {kind} {names[-1]} at ({fmt(x)}, {fmt(y)}, {fmt(z)}) m")
        print(f"    robot fetch at {STARTS.get(name, FETCH_START)} config tuck")
        print("  }")
        print("  goal {")
        for object_name, (_, x, y, z) in zip(names, targets):
            print(f"    at {object_name} ({fmt(x)}, {fmt(y)}, {fmt(z)}) m within 0.02 m 180 deg")
        print("  }")
        print("}")
        print()


# --- Keva and Jenga: structures and their problems ----------------------------------------------

RESTING_GAP = 0.001


def yawed(x, y, yaw_deg):
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    return c * x - s * y, s * x + c * y


def exact(value):
    """A coordinate to the hundredth of a millimetre, without trailing zeros: structures are
    built from millimetre gaps, which three decimals would round away."""
    text = f"{value:.5f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def pose_text(x, y, z, roll=0.0, pitch=0.0, yaw=0.0):
    text = f"({exact(x)}, {exact(y)}, {exact(z)}) m"
    if roll or pitch or yaw:
        text += f" rpy ({exact(roll)}, {exact(pitch)}, {exact(yaw)}) deg"
    return text


# A placement: (x, y, z, roll, pitch, yaw) in the anchor's frame, plus its box for the checks:
# (centre x, y, z, half sizes along the world axes after the yaw, as an axis-aligned box when the
# yaw is a multiple of 90 degrees, and the yaw).

PLANK_L, PLANK_W, PLANK_T = 0.117, 0.023, 0.007
PI_SPAN = 0.0775
PI_HEIGHT = RESTING_GAP + PLANK_L + RESTING_GAP + PLANK_T


def flat_plank(x, y, base, yaw):
    """A plank lying flat, long axis along `yaw`, on a support whose top is at `base`."""
    return (x, y, base + RESTING_GAP, 0.0, 0.0, yaw)


def upright_plank(x, y, base, yaw):
    """A plank standing on its end, 23 mm along `yaw` and 7 mm thick across it, centred at
    (x, y): rpy (0, -90, yaw + 90) turns its long axis up and its thickness (the frame's z, the
    frame at the bottom face) to -(across), so the frame sits 3.5 mm to the other side."""
    ox, oy = yawed(0.0, PLANK_T / 2, yaw)
    return (x + ox, y + oy, base + RESTING_GAP + PLANK_L / 2, 0.0, -90.0, yaw + 90.0)


def pi(cx, cy, base, yaw):
    """Two upright legs 7.75 cm apart along the lintel, which lies along `yaw` + 90 degrees; each
    leg is 23 mm wide across the lintel, so that the pi stands on a 23 mm × 85 mm footprint.
    Planks are listed in an order they can be built in: a gripper holds an upright by its top
    face, on the side its frame's z points to (-across), so the +across leg comes first and the
    other is then reached from outside the pi."""
    legs = []
    for side in (1, -1):
        lx, ly = yawed(0.0, side * PI_SPAN / 2, yaw)
        legs.append(upright_plank(cx + lx, cy + ly, base, yaw))
    lintel = flat_plank(cx, cy, base + RESTING_GAP + PLANK_L, yaw + 90.0)
    return legs + [lintel], base + PI_HEIGHT


def pi_stack(cx, cy, count, yaw=0.0):
    planks, base = [], 0.0
    for _ in range(count):
        more, base = pi(cx, cy, base, yaw)
        planks += more
    return planks


def log_cabin(cx, cy, layers):
    """Flat planks two per layer, 9 cm apart, each layer turned 90 degrees."""
    planks, base = [], 0.0
    for layer in range(layers):
        for side in (-1, 1):
            if layer % 2 == 0:
                planks.append(flat_plank(cx + side * 0.045, cy, base, 90.0))
            else:
                planks.append(flat_plank(cx, cy + side * 0.045, base, 0.0))
        base += RESTING_GAP + PLANK_T
    return planks


def house(cx, cy):
    """A floor plank, two walls standing on its ends, a ceiling, a post and a roof."""
    floor = flat_plank(cx, cy, 0.0, 90.0)
    top = RESTING_GAP + PLANK_T
    walls, ceiling_top = pi(cx, cy, top, 0.0)
    post = upright_plank(cx, cy, ceiling_top, 90.0)
    roof = flat_plank(cx, cy, ceiling_top + RESTING_GAP + PLANK_L, 0.0)
    return [floor] + walls + [post, roof]


def stonehenge(cx, cy, count, radius):
    planks = []
    for k in range(count):
        angle = 360.0 * k / count
        x, y = yawed(radius, 0.0, angle)
        planks += pi(cx + x, cy + y, 0.0, angle)[0]
    return planks


KEVA_STRUCTURES = [
    ("pi_tower", lambda: pi_stack(0, 0, 1), "A pi: two upright planks and a lintel across them."),
    ("flat_tower", lambda: log_cabin(0, 0, 2), "Two layers of two flat planks, crossed."),
    ("two_pi", lambda: pi_stack(-0.04, 0, 1) + pi_stack(0.04, 0, 1), "Two pis side by side."),
    ("house_2d", lambda: house(0, 0), "A floor, two walls, a ceiling, a post and a roof."),
    ("pi_tower", lambda: pi_stack(0, 0, 2), "Two pis, one on the other."),
    ("pi_tower", lambda: pi_stack(0, 0, 3), "Three stacked pis."),
    ("pi_row", lambda: sum((pi_stack(x, 0, 1) for x in (-0.08, 0.0, 0.08)), []),
     "Three pis in a row."),
    ("flat_tower", lambda: log_cabin(0, 0, 6), "Six crossed layers of two flat planks."),
    ("flat_twin", lambda: log_cabin(-0.07, 0, 4) + log_cabin(0.07, 0, 4),
     "Two towers of four crossed layers."),
    ("stonehenge", lambda: stonehenge(0, 0, 6, 0.15), "Six pis in a ring."),
    ("three_tower", lambda: sum((log_cabin(0, y, 4) for y in (-0.13, 0.0, 0.13)), []),
     "Three towers of four crossed layers in a row."),
    ("twin_stacked_pi", lambda: pi_stack(-0.04, 0, 5) + pi_stack(0.04, 0, 5),
     "Two stacks of five pis side by side."),
]

# The table (1.2 m square) stands clear of the YuMi's body (x from -0.65 m to -0.45 m).
KEVA_TABLE = (0.17, 0.0)
KEVA_SHOULDER = (-0.46, 0.0)
# Anchors nearest the YuMi first: from these, it reaches every placement of the bundled structures
# but the ring (measured with lamp's IK, the demonstrated grasp: an upright is held level, by its
# face, which the arm reaches low and far only with difficulty); farther out (x ≥ 0) it misses
# legs of the pis on the far side. A structure takes the first anchor, in its rotation of the
# list, that leaves room within reach for its supply; the last two always do.
KEVA_ANCHORS = [(-0.05, 0.10), (-0.10, 0.05), (-0.05, 0.0), (-0.10, 0.10), (-0.05, 0.05), (-0.10, 0.0)]
KEVA_FAR_ANCHORS = [(0.0, 0.10), (0.05, 0.05)]
# The ring (stonehenge) is 40 cm across: from every anchor above the YuMi misses one to five legs
# (those whose grasp side, where the fingers go, faces away from it). Turned 30° about an anchor
# at (-0.10, 0.10), it reaches all 18 placements (lamp's IK, the demonstrated grasp, on a 5 cm
# grid of anchors turned 0° and 30°), and the supply keeps 10 cm from the ring instead of 12 so
# that 18 spots stay within reach. Per structure stem: (anchors as (x, y, yaw), clearance).
KEVA_OWN_ANCHORS = {"stonehenge": ([(-0.10, 0.10, 30.0)], 0.10)}
KEVA_SUPPLY_CLEARANCE = 0.12


def footprint_corners(placement, length, width):
    """The corners (x, y) of a flat or upright plank's footprint, from its centre and yaw."""
    x, y, _, _, pitch, yaw = placement
    if pitch:  # upright: 23 mm along (yaw - 90), 7 mm across; the frame is 3.5 mm off centre
        ox, oy = yawed(0.0, -PLANK_T / 2, yaw - 90.0)
        cx, cy, hx, hy, angle = x + ox, y + oy, PLANK_W / 2, PLANK_T / 2, yaw - 90.0
    else:
        cx, cy, hx, hy, angle = x, y, length / 2, width / 2, yaw
    return [(cx + dx, cy + dy) for dx, dy in
            (yawed(sx * hx, sy * hy, angle) for sx in (-1, 1) for sy in (-1, 1))]


def supply(spots, count, keep_out, origin):
    """The `count` spots nearest `origin` that are farther than their clearance from every
    point of `keep_out`, or None if there are not so many."""
    free = [spot for spot in spots
            if all(math.hypot(spot[0] - px, spot[1] - py) > spot[2] for px, py in keep_out)]
    free.sort(key=lambda spot: (math.hypot(spot[0] - origin[0], spot[1] - origin[1]), spot))
    return free[:count] if len(free) >= count else None


# Where the YuMi's left arm takes a top grasp of a plank lying flat on the table: within this of
# a point beside its shoulder. Measured with lamp's IK (collision-free, from `home`) on a 5 cm grid,
# both yaws: every spot this close is reached, and some farther ones (towards +y and along x = 0).
KEVA_REACH_CENTRE = (-0.46, 0.1)
KEVA_REACH = 0.55
# The supply grid: 13 cm along a plank (11.7 cm and a gap), 6.5 cm across it (the fingers straddle
# a plank 2.4 to 3.4 cm from its centre line, clear of a neighbour's edge 5.35 cm away).
KEVA_SUPPLY_ALONG = 0.13
KEVA_SUPPLY_ACROSS = 0.065


def print_keva():
    rng = random.Random(20255)

    def spots_keeping(clearance):
        spots = []
        for i in range(8):
            for j in range(-12, 13):
                x, y = round(-0.35 + KEVA_SUPPLY_ALONG * i, 3), round(KEVA_SUPPLY_ACROSS * j, 3)
                if math.hypot(x - KEVA_REACH_CENTRE[0], y - KEVA_REACH_CENTRE[1]) <= KEVA_REACH:
                    spots.append((x, y, clearance + PLANK_L / 2))
        return spots
    names = []
    blocks = []
    for index, (stem, make, comment) in enumerate(KEVA_STRUCTURES):
        planks = make()
        name = f"{stem}_{len(planks)}"
        names.append(name)
        lines = [f"// {comment}", f"structure {name} {{"]
        for k, (x, y, z, roll, pitch, yaw) in enumerate(planks, start=1):
            lines.append(f"  plank p{k} at {pose_text(x, y, z, roll, pitch, yaw % 360)}")
        lines.append("}")
        blocks.append("\n".join(lines))
    print("\n\n".join(blocks))
    print()
    for index, (stem, make, _) in enumerate(KEVA_STRUCTURES):
        planks = make()
        name = names[index]
        first = index % len(KEVA_ANCHORS)
        anchors = [(x, y, 0.0) for x, y in
                   KEVA_ANCHORS[first:] + KEVA_ANCHORS[:first] + KEVA_FAR_ANCHORS]
        anchors, clearance = KEVA_OWN_ANCHORS.get(stem, (anchors, KEVA_SUPPLY_CLEARANCE))
        spots = spots_keeping(clearance)
        for ax, ay, ayaw in anchors:
            keep_out = []
            for plank in planks:
                for cx, cy in footprint_corners(plank, PLANK_L, PLANK_W):
                    dx, dy = yawed(cx, cy, ayaw)
                    keep_out.append((ax + dx, ay + dy))
            starts = supply(spots, len(planks), keep_out, KEVA_SHOULDER)
            if starts is not None:
                break
        assert starts is not None, name
        print(f"problem {name} {{")
        print("  scene {")
        print(f"    table table1 at {pose_text(*KEVA_TABLE, 0)}")
        print(f"    droparea area1 at {pose_text(ax, ay, 0, 0, 0, ayaw)}")
        for k, (x, y, _) in enumerate(starts, start=1):
            yaw = rng.choice([0, 0, 180])
            print(f"    plank p{k} at {pose_text(x, y, RESTING_GAP, 0, 0, yaw)}")
        print("    robot yumi config home")
        print("  }")
        print("  goal {")
        print(f"    structure {name} at area1")
        print("  }")
        print("}")
        print()


BLOCK_L, BLOCK_W, BLOCK_H = 0.1524, 0.0508, 0.03048
JENGA_TABLE = (0.7, 0.0, 0.459)  # the table's top centre; its top is 0.6 m × 0.9 m
JENGA_SHOULDER = (0.12, 0.0)
JENGA_COUNTS = [2, 3, 4, 6, 6, 8, 10, 12, 12, 14, 16, 18, 24, 30]


def tower(count):
    """Layers of two blocks at ±0.0508 m across, each turned 90 degrees from the one below."""
    blocks = []
    for k in range(count):
        layer, side = divmod(k, 2)
        z = RESTING_GAP + layer * (BLOCK_H + RESTING_GAP) + BLOCK_H / 2
        offset = (1 - 2 * side) * BLOCK_W if not (k == count - 1 and side == 0) else BLOCK_W
        if layer % 2 == 0:
            blocks.append((0.0, offset, z, 0.0, 0.0, 0.0))
        else:
            blocks.append((offset, 0.0, z, 0.0, 0.0, 90.0))
    return blocks


def print_jenga():
    rng = random.Random(20256)
    tx, ty, tz = JENGA_TABLE
    sizes = sorted(set(JENGA_COUNTS))
    blocks_text = []
    for count in sizes:
        lines = [f"// {count} blocks: layers of two at the outer positions, each turned 90 degrees"
                 + (", one block on top." if count % 2 else "."), f"structure tower_{count} {{"]
        for k, (x, y, z, roll, pitch, yaw) in enumerate(tower(count), start=1):
            lines.append(f"  block b{k} at {pose_text(x, y, z, roll, pitch, yaw)}")
        lines.append("}")
        blocks_text.append("\n".join(lines))
    print("\n\n".join(blocks_text))
    print()
    seen = {}
    for count in JENGA_COUNTS:
        seen[count] = seen.get(count, 0) + 1
        name = f"tower_{count}" + ("" if seen[count] == 1 else "_b")
        # The table's spots first; the side tables only when the table's free spots are too few.
        tables = [("table", "table1", (tx, ty))]
        for attempt in range(1000):
            ax = round(rng.uniform(tx - 0.12, tx + 0.12), 2)
            ay = round(rng.uniform(ty - 0.25, ty + 0.25), 2)
            yaw = rng.choice([0, 0, 15, 30, 45, 60, 90])
            blocks = [(ax + x2, ay + y2, z, byaw + yaw) for (x, y, z, _, _, byaw) in tower(count)
                      for x2, y2 in [yawed(x, y, yaw)] if z < 0.1]
            free = [spot for spot in JENGA_TABLE_SPOTS if all(
                supply_clear(spot, (bx, by), byaw) for bx, by, _, byaw in blocks)]
            if len(free) >= count or (len(free) + len(JENGA_SIDE_SPOTS) >= count and attempt > 200):
                break
        else:
            raise AssertionError(f"no anchor leaves {count} spots free")
        if len(free) < count:
            free += JENGA_SIDE_SPOTS
            tables += [("side_table", f"side{k}", pose) for k, pose in
                       enumerate(JENGA_SIDE_TABLES, start=1)]
        free.sort(key=lambda s: (math.hypot(s[0] - JENGA_SHOULDER[0], s[1] - JENGA_SHOULDER[1]), s))
        print(f"problem {name} {{")
        print("  scene {")
        for kind, table, (x, y) in tables:
            print(f"    {kind} {table} at {pose_text(x, y, tz)}")
        print(f"    build_area area1 at {pose_text(ax, ay, tz, 0, 0, yaw)}")
        for k, (x, y) in enumerate(free[:count], start=1):
            print(f"    block b{k} at {pose_text(x, y, tz + RESTING_GAP + BLOCK_H / 2)}")
        print("    robot fetch config tuck")
        print("  }")
        print("  goal {")
        print(f"    structure tower_{count} at area1")
        print("  }")
        print("}")
        print()


# Supply spots for blocks lying flat, long axis along x (toward the Fetch), so that its fingers
# close across y: 0.2 m apart along x (4.8 cm between block ends) and 0.1 m across (4.9 cm
# between neighbours: an open pad, 1.4 cm outside the block it grasps and 1.4 cm thick, keeps
# 2.1 cm from the next block). Every spot is outside every other's block–block bins (±0.075 m).
# The arm reaches a top grasp everywhere on the table within ±0.21 m along and ±0.4 m across.
JENGA_TABLE_SPOTS = [(round(0.7 + 0.2 * i, 3), round(0.1 * j, 3))
                     for i in (-1, 0, 1) for j in range(-4, 5)]
# Side tables (0.5 m × 0.3 m, the table's height) either side of the Fetch, for towers with more
# blocks than the table holds beside them; their spots are within the arm's reach too.
JENGA_SIDE_TABLES = [(0.45, 0.64), (0.45, -0.64)]
JENGA_SIDE_SPOTS = [(x, round(sy * y, 3)) for sy in (1, -1)
                    for x in (0.285, 0.45, 0.615) for y in (0.59, 0.69)]


def supply_clear(spot, block, block_yaw):
    """Whether a supply block at `spot` (yaw 0) lies outside the block–block bins of a tower block
    and its bins outside the tower block's, with 1 cm to spare, and 4 cm clear of its footprint
    (an open finger reaches 2.8 cm beside the block it grasps)."""
    if not outside_block_bins(spot, 0.0, block, block_yaw):
        return False
    ours = (spot[0], spot[1], 0.0)
    theirs = (block[0], block[1], block_yaw)
    for (ax, ay, ayaw), (bx, by, byaw) in ((ours, theirs), (theirs, ours)):
        points = footprint_corners((bx, by, 0, 0, 0, byaw), BLOCK_L, BLOCK_W) + [(bx, by)]
        if any(rectangle_distance(px, py, ax, ay, ayaw, BLOCK_L / 2, BLOCK_W / 2) <= 0.04
               for px, py in points):
            return False
    return True


def outside_block_bins(spot, spot_yaw, other, other_yaw):
    """Whether two blocks on the table lie outside each other's block–block bins (±0.075 m along
    and across a block), with 1 cm to spare."""
    for (ax, ay, ayaw), (bx, by) in (((spot[0], spot[1], spot_yaw), other),
                                     ((other[0], other[1], other_yaw), spot)):
        lx, ly = yawed(bx - ax, by - ay, -ayaw)
        if abs(lx) <= 0.085 and abs(ly) <= 0.085:
            return False
    return True


if __name__ == "__main__":
    which = sys.argv[1] if len(sys.argv) > 1 else ""
    if which == "packing":
        print_packing()
    elif which == "cafe":
        print_cafe()
    elif which == "cafe-layouts":
        print_cafe_layouts()
    elif which == "dinner":
        print_dinner()
    elif which == "keva":
        print_keva()
    elif which == "jenga":
        print_jenga()
    else:
        sys.exit("usage: make_problems.py packing|cafe|cafe-layouts|dinner|keva|jenga")
