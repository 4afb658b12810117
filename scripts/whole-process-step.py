#!/usr/bin/env python3
"""Whole-process time per step of `extremal report` on scene files, for builds without the
JSON summary's step times (issue 32's measure): (wall of the scene's N steps - wall of its first
step alone) / (N - 1), start-up, import and row writing included, median over RUNS runs that
alternate the binaries. The one-step copy of each scene is written beside it (so relative file
paths hold) and removed afterwards. Usage:
    scripts/whole-process-step.py RUNS SCENE.json... -- BINARY...
The import's time varies from run to run by up to a second on a shared machine, which this
difference does not cancel: read only large ratios, and more runs where single runs disagree."""
import json, os, statistics, subprocess, sys, tempfile, time

def main():
    args = sys.argv[1:]
    if len(args) < 4 or '--' not in args:
        sys.exit(__doc__)
    runs, sep = int(args[0]), args.index('--')
    scenes, binaries = args[1:sep], args[sep + 1:]
    out = os.path.join(tempfile.mkdtemp(), 'rows.csv')

    def wall(binary, scene):
        start = time.perf_counter()
        subprocess.run([binary, 'report', scene, '-o', out, '--quiet'], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return time.perf_counter() - start

    for scene in scenes:
        spec = json.load(open(scene))
        t = spec['time']
        n = int(round((t['end'] - t['start']) / t['step'])) + 1
        if n < 2:
            sys.exit(f'{scene}: one step only, nothing to difference')
        one = dict(spec, time=dict(t, end=t['start']))
        one_path = os.path.join(os.path.dirname(os.path.abspath(scene)), '.one_step_' + os.path.basename(scene))
        with open(one_path, 'w') as f:
            json.dump(one, f)
        try:
            per_step = {b: [] for b in binaries}
            for _ in range(runs):
                for b in binaries:
                    per_step[b].append((wall(b, scene) - wall(b, one_path)) / (n - 1) * 1e6)
        finally:
            os.remove(one_path)
        cells = ['%s: %.1f us (runs %s)' % (b, statistics.median(v), ', '.join('%.0f' % x for x in v))
                 for b, v in per_step.items()]
        print(os.path.basename(scene), n, 'steps;', '; '.join(cells), flush=True)

if __name__ == '__main__':
    main()
