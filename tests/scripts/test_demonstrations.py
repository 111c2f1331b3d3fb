#!/usr/bin/env python3
"""scripts/demonstrations.sh: the five demonstrations' commands, their order and hand-offs, and a
run through a stand-in binary (one demonstration failing) that gathers the others' table.

Run by ctest (tests/CMakeLists.txt) as `python3 tests/scripts/test_demonstrations.py SOURCE_DIR`.
"""
import json
import os
import re
import stat
import subprocess
import sys
import tempfile
import unittest

SOURCE = None  # set from argv in __main__

# A stand-in for rbaa: `attack --out=D` writes D/adversarial.msh, `evaluate --out=D` a report with
# one outcome, `export --out=D` the folder; the bunny's evaluation fails. Every call is logged.
STUB = r"""#!/usr/bin/env python3
import json, os, sys
args = sys.argv[1:]
with open(os.environ["STUB_CALLS"], "a") as f:
    f.write(" ".join(args) + "\n")
out = next(a[len("--out="):] for a in args if a.startswith("--out="))
os.makedirs(out, exist_ok=True)
if args[0] == "attack":
    open(os.path.join(out, "adversarial.msh"), "w").write("stub\n")
elif args[0] == "evaluate":
    if any("bunny_bin" in a for a in args) and os.environ.get("STUB_BIN_FAILS", "1") == "1":
        sys.exit("stub: the bin's evaluation fails")
    runs = [{"simulator": s, "object": o, "run": s + " " + o, "detail": "-", "predicate": True}
            for s in ("rigid", "deformable") for o in ("reference", "adversarial")]
    outcomes = {"predicate": "stands", "runs": runs}
    if any("star" in a for a in args) and os.environ.get("STUB_STAR_NO_OUTCOMES") == "1":
        outcomes = None  # a config without its demonstration block
    json.dump({"outcomes": outcomes, "time_step_s": 0.001,
               "baseline_disagreement": 0.01, "rigid_vs_rigid": {"max_com_gap_m": 0.0},
               "timing_s": {}}, open(os.path.join(out, "report.json"), "w"))
"""


def write_stub(directory):
    """The stand-in rbaa in `directory`, executable; its path."""
    stub = os.path.join(directory, "rbaa")
    with open(stub, "w") as f:
        f.write(STUB)
    os.chmod(stub, os.stat(stub).st_mode | stat.S_IEXEC)
    return stub


def run(*args, env=None):
    p = subprocess.run(["bash", os.path.join(SOURCE, "scripts", "demonstrations.sh"), *args],
                       capture_output=True, text=True, env=env)
    return p.returncode, p.stdout, p.stderr


def read(path):
    with open(path) as f:
        return f.read()


def plan(stdout):
    """{demo: [command, ...]} in the order printed."""
    demos, current = {}, None
    for line in stdout.splitlines():
        if " " not in line:
            current = line
            demos[current] = []
        else:
            demos[current].append(line.split())
    return demos


def base_of(config):
    """The config a config is laid over (its `base:`), as a path from the source folder."""
    with open(os.path.join(SOURCE, config)) as f:
        m = re.search(r"(?m)^base: (\S+)", f.read())
    return m and os.path.normpath(os.path.join(os.path.dirname(config), m.group(1)))


def flag(command, name):
    return next((a.split("=", 1)[1] for a in command if a.startswith(name + "=")), None)


class Demonstrations(unittest.TestCase):
    def test_each_demonstration_attacks_evaluates_and_exports_its_own_object(self):
        code, out, err = run("--dry-run", "--out=/x/demos")
        self.assertEqual(code, 0, err)
        demos = plan(out)
        self.assertEqual(list(demos), ["bat", "hoop", "bin", "stack", "star"])  # longest first
        scenes = {"bat": "bat", "hoop": "ball_hoop", "bin": "bunny_bin", "stack": "cube_stack",
                  "star": "star"}
        for name, (attack, evaluate, export) in demos.items():
            self.assertEqual([attack[1], evaluate[1], export[1]], ["attack", "evaluate", "export"])
            for c in (attack, evaluate, export):
                config = flag(c, "--config")
                self.assertTrue(os.path.isfile(os.path.join(SOURCE, config)), config)
            self.assertEqual(flag(evaluate, "--config"), f"configs/demos/{scenes[name]}.yaml")
            self.assertEqual(flag(export, "--config"), flag(evaluate, "--config"))
            # The object evaluated and exported is the one this attack wrote.
            made = flag(attack, "--out") + "/adversarial.msh"
            self.assertTrue(made.startswith("/x/demos/"), made)
            self.assertEqual(flag(evaluate, "--adversarial"), made)
            self.assertEqual(flag(export, "--adversarial"), made)
            self.assertEqual(flag(evaluate, "--out"), f"/x/demos/{name}")
            self.assertEqual(flag(export, "--format"), "polyfem")
            # The demonstration is laid over the attack's config or over the scene that config
            # is laid over (the bin's and bunny_accurate's: bunny.yaml).
            demo_base = base_of(flag(evaluate, "--config"))
            attacked = flag(attack, "--config")
            self.assertIn(demo_base, (os.path.normpath(attacked), base_of(attacked)), name)
        # The stack's cubes at the same resolution in the attack, the evaluation and the export.
        for c in demos["stack"]:
            self.assertEqual(flag(c, "--set"), "mesh.target_tets=1500")

    def test_a_subset_and_bad_arguments(self):
        code, out, _ = run("--dry-run", "--only=star,hoop")
        self.assertEqual((code, list(plan(out))), (0, ["hoop", "star"]))
        for bad, named in (("--only=star,nope", "'nope'"), ("--jobs=0", "--jobs=0"),
                           ("--jobs=two", "--jobs=two"), ("--frobnicate", "'--frobnicate'"),
                           ("--out=a b", "space")):
            code, out, err = run("--dry-run", bad)
            self.assertEqual(code, 2, bad)
            self.assertEqual(out, "", bad)
            self.assertEqual(len(err.strip().splitlines()), 1, err)
            self.assertIn(named, err)

    def test_a_failed_demonstration_is_reported_and_the_others_are_tabled(self):
        with tempfile.TemporaryDirectory() as tmp:
            calls = os.path.join(tmp, "calls.txt")
            env = dict(os.environ, RBAA=write_stub(tmp), STUB_CALLS=calls)
            out_dir = os.path.join(tmp, "demos")
            code, out, err = run(f"--out={out_dir}", "--jobs=3", env=env)
            self.assertEqual(code, 1, err)
            self.assertIn("bin 2 FAILED", err)
            with open(calls) as f:
                made = [line.split()[0] for line in f]
            self.assertEqual(made.count("attack"), 5)
            self.assertEqual(made.count("evaluate"), 5)
            self.assertEqual(made.count("export"), 4)  # not the failed bin's
            table = read(os.path.join(out_dir, "outcomes.md"))
            self.assertEqual(out, table)
            for name in ("hoop", "stack", "star", "bat"):
                self.assertIn(f"| {name} |", table)
            self.assertNotIn("| bin |", table)
            log = read(os.path.join(out_dir, "times.log"))
            self.assertIn("bin 2 FAILED", log)
            self.assertIn("stub: the bin's evaluation fails",
                          read(os.path.join(out_dir, "logs", "bin.2.log")))
            for name in ("hoop", "stack", "star", "bat"):
                self.assertIn(f"{name} 3 done", log)

    def test_a_table_that_cannot_be_made_fails_the_run_and_leaves_no_table(self):
        with tempfile.TemporaryDirectory() as tmp:
            env = dict(os.environ, RBAA=write_stub(tmp), STUB_CALLS=os.path.join(tmp, "calls.txt"),
                       STUB_BIN_FAILS="0", STUB_STAR_NO_OUTCOMES="1")
            out_dir = os.path.join(tmp, "demos")
            os.makedirs(out_dir)
            with open(os.path.join(out_dir, "outcomes.md"), "w") as f:
                f.write("an earlier run's table\n")
            code, out, err = run(f"--out={out_dir}", "--jobs=3", env=env)
            self.assertEqual(code, 1, err)
            self.assertIn("no 'outcomes'", err)
            self.assertFalse(os.path.exists(os.path.join(out_dir, "outcomes.md")))

    def test_a_binary_path_with_a_space_is_refused(self):
        env = dict(os.environ, RBAA="/tmp/my dir/rbaa")
        code, out, err = run("--dry-run", env=env)
        self.assertEqual((code, out), (2, ""), err)
        self.assertEqual(len(err.strip().splitlines()), 1, err)
        self.assertIn("space", err)


if __name__ == "__main__":
    SOURCE = sys.argv.pop(1)
    unittest.main()
