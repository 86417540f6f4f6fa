#!/usr/bin/env python3
"""One solve of `lampc eval`, run as a task on a Ray cluster.

Used as `lampc eval ... --executor "python3 domains/tools/ray_eval_worker.py"`: it speaks the
protocol of `lampc eval-worker` (docs/evaluation.md, "Executors"). It reads the job from its
standard input, runs `lampc eval-worker` on it as a Ray task (one CPU) on whichever node the
cluster picks, and prints the task's result row on its standard output; the worker's standard
error follows on its own, and a line saying which node solved it.

The cluster is the one `RAY_ADDRESS` names (as `ray start` prints it), else a local one started
with `ray start --head` (`address="auto"`). Every node must run the same lampc build and see the
spec and the files it names at the same paths (a shared file system): the task runs in the
folder this script was started in (`lampc eval`'s own, which the job's relative spec path is
relative to), and `--lampc PATH` gives the node's lampc when it is not `lampc` on its PATH.

A failure of the cluster (a node lost, a worker killed, the cluster unreachable) is written to
standard error and the script exits with 1, so that `lampc eval` reports it for that solve and
tries it once more; Ray itself retries nothing. Stopped by SIGTERM or SIGINT (as `lampc eval`
stops its executors), it cancels the task on the cluster before it exits.
"""

import argparse
import os
import signal
import subprocess
import sys


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--lampc", default="lampc", help="the lampc a node runs (default: lampc on its PATH)"
    )
    parser.add_argument(
        "--address", default=None, help="the Ray cluster (default: RAY_ADDRESS, else auto)"
    )
    options = parser.parse_args()
    job = sys.stdin.buffer.read()

    try:
        import ray
    except ImportError:
        sys.stderr.write("ray_eval_worker: python3 cannot import ray (pip install ray)\n")
        return 1

    @ray.remote(num_cpus=1, max_retries=0)
    def solve(lampc, folder, job):
        import socket

        done = subprocess.run([lampc, "eval-worker"], input=job, capture_output=True, cwd=folder)
        node = f"{socket.gethostname()} ({ray.get_runtime_context().get_node_id()[:12]})"
        return done.returncode, done.stdout, done.stderr, node

    try:
        ray.init(
            address=options.address,
            logging_level="ERROR",
            log_to_driver=False,
            configure_logging=False,
        )
    except Exception as error:  # noqa: BLE001 - any failure to connect is the cluster's
        sys.stderr.write(f"ray_eval_worker: cannot connect to the Ray cluster: {error}\n")
        return 1

    task = solve.remote(options.lampc, os.getcwd(), job)

    def stop(signum, _frame):
        ray.cancel(task, force=True)
        sys.stderr.write(f"ray_eval_worker: stopped by signal {signum}; the task is cancelled\n")
        sys.exit(128 + signum)

    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    try:
        code, out, err, node = ray.get(task)
    except Exception as error:  # noqa: BLE001 - a lost node or worker is the cluster's failure
        sys.stderr.write(f"ray_eval_worker: the task failed on the cluster: {error}\n")
        return 1
    sys.stderr.buffer.write(err)
    sys.stderr.write(f"ray_eval_worker: solved on node {node}\n")
    sys.stdout.buffer.write(out)
    sys.stdout.flush()
    return code


if __name__ == "__main__":
    sys.exit(main())
