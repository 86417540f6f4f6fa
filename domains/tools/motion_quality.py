"""How long a solution's motions are against the shortest they could be.

    python3 domains/tools/motion_quality.py SOLUTION/trajectory.mcap [...] [--markdown]

Reads the joint trajectories a solution carries for controllers (`/lamp/joint_trajectory`,
`/lamp/base_trajectory`, and their per-robot forms, `docs/formats.md`). For each motion it sums
the joint-space distance between consecutive points (path length) and takes the straight
joint-space distance between its first and last points (a lower bound no path between them can
beat), and it sums the time the motion takes. Arm joints are in radians (a prismatic torso in
metres); a mount mixes metres and radians, so mounts are reported apart from arms. A motion that
only waits (the fingers closing or opening) is left out.
"""

import argparse
import math
import statistics
import sys

from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory


def motions(path):
    """(topic, path length, straight distance, seconds) for every motion in the file."""
    with open(path, "rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        topics = [
            channel.topic
            for channel in reader.get_summary().channels.values()
            if channel.topic.endswith(("lamp/joint_trajectory", "lamp/base_trajectory"))
        ]
        for _, channel, _, decoded in reader.iter_decoded_messages(topics=topics):
            points = [list(point.positions) for point in decoded.points]
            if len(points) < 2:
                continue
            length = sum(math.dist(a, b) for a, b in zip(points, points[1:]))
            straight = math.dist(points[0], points[-1])
            end = decoded.points[-1].time_from_start
            seconds = end.sec + end.nanosec / 1e9
            if length > 0.0:
                yield channel.topic, length, straight, seconds


def rows(paths):
    for path in paths:
        by_topic = {}
        for topic, length, straight, seconds in motions(path):
            by_topic.setdefault(topic, []).append((length, straight, seconds))
        for topic, found in sorted(by_topic.items()):
            length = sum(item[0] for item in found)
            straight = sum(item[1] for item in found)
            ratios = sorted(item[0] / item[1] for item in found if item[1] > 1e-9)
            p90 = ratios[min(len(ratios) - 1, int(0.9 * len(ratios)))] if ratios else float("nan")
            yield {
                "solution": path,
                "topic": topic,
                "motions": len(found),
                "length": length,
                "straight": straight,
                "ratio": length / straight if straight > 0 else float("nan"),
                "median": statistics.median(ratios) if ratios else float("nan"),
                "p90": p90,
                "seconds": sum(item[2] for item in found),
            }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("solutions", nargs="+", help="trajectory.mcap files")
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = parser.parse_args()
    header = ["solution", "topic", "motions", "path length", "straight bound", "ratio",
              "median ratio", "p90 ratio", "motion seconds"]
    if args.markdown:
        print("| " + " | ".join(header) + " |")
        print("| " + " | ".join(["---"] * 2 + ["---:"] * (len(header) - 2)) + " |")
    for row in rows(args.solutions):
        cells = [row["solution"], row["topic"], str(row["motions"]), f"{row['length']:.1f}",
                 f"{row['straight']:.1f}", f"{row['ratio']:.2f}", f"{row['median']:.2f}",
                 f"{row['p90']:.2f}", f"{row['seconds']:.1f}"]
        print(("| " + " | ".join(cells) + " |") if args.markdown else "  ".join(cells))
    return 0


if __name__ == "__main__":
    sys.exit(main())
