"""Batch reports on a Dask distributed cluster.

    python3 -m extremal.batch SCENES... -o OUT.csv|OUT.json [--scheduler ADDRESS] [--workers N]
                              [--threads N] [--split auto|scene|pair] [--ship] [--quiet]
                              [--connect-timeout SECONDS]

writes the files `extremal report SCENES... -o OUT` writes, named as it names them (OUT itself
for one scene; OUT.<stem>.<ext> for several, <k>-<stem> for every scene when two share a stem),
the CSV byte for byte and the JSON equal but for its timing fields (step_time_us: the step times
the workers measured, per pair and per scene, differ from run to run). Without --scheduler it starts a local cluster of N
worker processes (default: one per CPU).

How (run(), the same from Python): every scene is read and checked here first, as the command
reads them, so a bad scene stops the batch before any task runs. Then one task per scene, or
one per body pair of a scene (--split pair; 'auto' splits the scenes of a batch that has fewer
scenes than the cluster has worker threads). A pair runs alone exactly as it does among its
scene's pairs (each pair has a tracker of its own), so a split scene's rows are put back in
order and its summary rebuilt here, through the command's own writer, whatever the split.

Workers read the scene files, and the files they name, from a path they share with this
machine (give paths that mean the same there: absolute, or relative to the workers' working
folder), or with --ship get them shipped: this machine reads the scene and every CAD file and
pose table it names, and the workers write them to a temporary folder for the task. The
reports name the scenes and files by the paths given here either way.

Dask is imported by this module only (`import extremal` does not need it).
"""

import argparse
import dataclasses
import json
import os
import sys
import tempfile

from distributed import Client, LocalCluster, as_completed

from . import InvalidInput, _core

__all__ = ["ShippedScene", "main", "run", "ship"]


@dataclasses.dataclass(frozen=True)
class ShippedScene:
    """A scene file with the files it names, to run where they are not.

    path: the scene's path as given (its report names it so, and resolves its entries from it);
    text: the scene file's bytes; files: each named file's bytes by the path the scene resolves
    it to; tables: (body index, resolved path) of the bodies moved by pose tables."""

    path: str
    text: bytes
    files: dict
    tables: tuple


def _read_bytes(path, what):
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError as e:
        raise InvalidInput(f"{what}: cannot read {path}: {e.strerror}") from None


def _pack(path):
    text = _read_bytes(path, path)
    scene = json.loads(text)  # read and checked by _core._read_outline already
    files, tables = {}, []
    for i, body in enumerate(scene["bodies"]):
        if "file" in body:
            resolved = _core._resolve_scene_file(path, body["file"])
            files[resolved] = _read_bytes(resolved, f"{path}: bodies[{i}].file")
        motion = body.get("motion", {})
        if motion.get("type") == "table":
            resolved = _core._resolve_scene_file(path, motion["file"])
            files[resolved] = _read_bytes(resolved, f"{path}: bodies[{i}].motion.file")
            tables.append((i, resolved))
    return ShippedScene(path, text, files, tuple(tables))


def ship(scene):
    """Reads and checks a scene file as `extremal report` does, and packs it with the files it
    names into a ShippedScene (which run() takes in place of a path)."""
    path = os.fspath(scene)
    _core._read_outline(path)
    return _pack(path)


def _materialize(shipped, folder):
    """Writes a shipped scene's files into `folder`; returns the scene's text and the map from
    the paths the scene names to the copies."""
    local = {}
    for k, (resolved, data) in enumerate(shipped.files.items()):
        where = os.path.join(folder, str(k))
        os.makedirs(where, exist_ok=True)
        # The same file name: readers choose by content first, then by extension.
        copy = os.path.join(where, os.path.basename(resolved) or "file")
        with open(copy, "wb") as f:
            f.write(data)
        local[resolved] = copy
    text = shipped.text
    if shipped.tables:
        # A pose table is read where the scene names it (and named nowhere in the report): the
        # scene's text names the copy instead.
        scene = json.loads(shipped.text)
        for i, resolved in shipped.tables:
            scene["bodies"][i]["motion"]["file"] = local[resolved]
        text = json.dumps(scene).encode("utf-8")
    return text, local


def _run_part(scene, pairs, threads):
    """A task: the rows of some (None: all) of a scene's pairs, as arrays."""
    if isinstance(scene, ShippedScene):
        with tempfile.TemporaryDirectory(prefix="extremal-batch-") as folder:
            text, files = _materialize(scene, folder)
            return _core._run_scene(scene.path, pairs, threads, text, files)
    return _core._run_scene(scene, pairs, threads)


def _prepare(scene, shipping):
    """The scene's outline (read and checked here) and what a task gets: its path or the
    shipped scene."""
    if isinstance(scene, ShippedScene):
        with tempfile.TemporaryDirectory(prefix="extremal-batch-") as folder:
            text, files = _materialize(scene, folder)
            return _core._read_outline(scene.path, text, files), scene
    try:
        path = os.fspath(scene)
    except TypeError:
        path = None
    if not isinstance(path, str):
        raise InvalidInput(f"scenes: expected paths (or ShippedScene), got {type(scene).__name__}")
    outline = _core._read_outline(path)
    return outline, (_pack(path) if shipping else path)


def run(scenes, output, client=None, *, workers=None, split="auto", threads=1, ship=False,
        quiet=True, out=None):
    """Runs a batch of scene files on a Dask cluster and writes their reports as
    `extremal report SCENES... -o OUTPUT` does; returns the files written, in scene order.

    scenes: paths (or ShippedScene); output: OUT.csv or OUT.json; client: a
    distributed.Client (None: a LocalCluster of `workers` processes, one thread each, default
    one per CPU, closed at the end); split: 'scene' (one task per scene), 'pair' (one per body
    pair) or 'auto' (per pair when there are fewer scenes than worker threads); threads: the
    threads each task runs its pairs on; ship: send the scene files and the files they name to
    the workers instead of having them read a shared path; quiet: False prints each scene's
    summary (as the command does) to `out` (default stdout), in scene order.

    Raises extremal.InvalidInput naming the scene file and the JSON path or file, before any
    task runs for a bad scene; a task's error is raised here, the scenes done before it
    written.
    """
    output = os.fspath(output)
    if not (output.endswith(".csv") or output.endswith(".json")):
        raise InvalidInput(f"-o {output}: expected a file name ending in .csv or .json")
    if split not in ("auto", "scene", "pair"):
        raise InvalidInput(f"split: expected 'auto', 'scene' or 'pair', got {split!r}")
    if not isinstance(threads, int) or threads < 1:
        raise InvalidInput(f"threads: must be at least 1, got {threads!r}")
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise InvalidInput(f"workers: must be at least 1, got {workers!r}")
    if client is not None and workers is not None:
        raise InvalidInput("workers: starts a local cluster, not with a client")
    scenes = list(scenes)
    if not scenes:
        raise InvalidInput("scenes: no scene files")
    # Every scene is read and checked before any runs.
    prepared = [_prepare(s, ship) for s in scenes]
    outputs = _core._output_names([outline.path for outline, _ in prepared], output)
    out = sys.stdout if out is None else out

    cluster = None
    if client is None:
        cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                               processes=True, dashboard_address=None)
        client = Client(cluster)
    futures = []
    try:
        slots = sum(client.nthreads().values()) or 1
        owner = {}  # future -> scene index
        remaining = []
        parts = [[] for _ in scenes]
        for i, (outline, task_scene) in enumerate(prepared):
            n_pairs = len(outline.pairs)
            by_pair = split == "pair" or (split == "auto" and n_pairs > 1 and len(scenes) < slots)
            if isinstance(task_scene, ShippedScene):
                task_scene = client.scatter(task_scene, hash=False)
            groups = [[k] for k in range(n_pairs)] if by_pair else [None]
            for group in groups:
                f = client.submit(_run_part, task_scene, group, threads, pure=False)
                owner[f] = i
                futures.append(f)
            remaining.append(len(groups))
        summaries = [None] * len(scenes)
        printed = 0
        for f in as_completed(futures):
            i = owner[f]
            parts[i].append(f.result())
            f.release()
            remaining[i] -= 1
            if remaining[i]:
                continue
            summaries[i] = _core._write_report(prepared[i][0], outputs[i], parts[i])
            parts[i] = None
            while printed < len(scenes) and summaries[printed] is not None:
                if not quiet:
                    out.write(summaries[printed])
                    out.flush()
                printed += 1
    except BaseException:
        client.cancel(futures)
        raise
    finally:
        if cluster is not None:
            client.close()
            cluster.close()
    return outputs


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="python3 -m extremal.batch",
        description="Batch distance reports over time on a Dask cluster: the files `extremal "
        "report SCENES... -o OUT` writes.",
        epilog="Exit codes: 0 success, 1 bad input (message on stderr), 2 usage error. "
        "docs/python.md, 'Batches on several machines', shows how to start a cluster.")
    parser.add_argument("scenes", nargs="+", metavar="SCENE", help="scene file(s) (JSON)")
    parser.add_argument("-o", "--output", required=True, metavar="OUT",
                        help="OUT.csv or OUT.json; several scenes write OUT.<stem>.<ext>")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="a running Dask scheduler (tcp://host:8786); default: a local cluster")
    parser.add_argument("--connect-timeout", type=float, default=30.0, metavar="SECONDS",
                        help="how long to try reaching --scheduler (default 30)")
    parser.add_argument("--workers", type=int, metavar="N",
                        help="worker processes of the local cluster (default: one per CPU)")
    parser.add_argument("--threads", type=int, default=1, metavar="N",
                        help="threads each task runs its pairs on (default 1)")
    parser.add_argument("--split", choices=("auto", "scene", "pair"), default="auto",
                        help="one task per scene or per body pair (auto: per pair when there "
                        "are fewer scenes than worker threads)")
    parser.add_argument("--ship", action="store_true",
                        help="send the scene files and the files they name to the workers "
                        "(default: the workers read them from the same paths)")
    parser.add_argument("--quiet", action="store_true", help="no summaries")
    args = parser.parse_args(argv)
    if args.scheduler and args.workers is not None:
        parser.error("--workers starts a local cluster: not with --scheduler")
    if args.workers is not None and args.workers < 1:
        parser.error(f"--workers {args.workers}: must be at least 1")
    if args.threads < 1:
        parser.error(f"--threads {args.threads}: must be at least 1")
    client = None
    try:
        if args.scheduler:
            try:
                client = Client(args.scheduler, timeout=args.connect_timeout)
            except (OSError, TimeoutError) as e:
                raise InvalidInput(f"--scheduler {args.scheduler}: cannot connect: {e}") from None
        run(args.scenes, args.output, client, workers=args.workers, split=args.split,
            threads=args.threads, ship=args.ship, quiet=args.quiet)
    except InvalidInput as e:
        print(f"extremal.batch: {e}", file=sys.stderr)
        return 1
    finally:
        if client is not None:
            client.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
