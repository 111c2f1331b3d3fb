#!/usr/bin/env python3
"""scripts/outcome_table.py: its cells from a report's outcomes, and one-line errors for bad input.

Run by ctest (tests/CMakeLists.txt) as `python3 tests/scripts/test_outcome_table.py SOURCE_DIR`.
The round trip from a real `rbaa evaluate` output is in tests/eval/test_evaluation_demonstration.cpp.
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = None  # set from argv in __main__


def run(*args):
    p = subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def outcome(simulator, obj, predicate=None, figure=None):
    run_name = f"{simulator} {obj}"
    r = {"simulator": simulator, "object": obj, "run": run_name, "detail": "-"}
    if predicate is not None:
        r["predicate"] = predicate
    if figure is not None:
        r["figure_deg"] = figure
    return r


def write_report(directory, report):
    os.makedirs(directory, exist_ok=True)
    with open(os.path.join(directory, "report.json"), "w") as f:
        json.dump(report, f)


class OutcomeTable(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.dir = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def test_cells_say_what_each_run_measured(self):
        d = os.path.join(self.dir, "hoop")
        write_report(d, {
            "outcomes": {"predicate": "through_hoop", "figure": "angle", "runs": [
                outcome("rigid", "reference", True, 0.0),
                outcome("rigid", "adversarial", True, 0.0),
                outcome("deformable", "reference", True, 9.389),
                outcome("deformable", "adversarial", False, 4.2),
                # no deformable soft control: "not run", never a guess
            ]},
            "time_step_s": 0.0025, "baseline_disagreement": 0.086,
            "rigid_vs_rigid": {"max_com_gap_m": 0.0},
            "timing_s": {"rigid reference": 1.0, "rigid adversarial": 2.0,
                         "deformable reference": 30.0, "deformable adversarial": 40.0},
        })
        code, out, err = run(f"hoop={d}")
        self.assertEqual(code, 0, err)
        lines = out.splitlines()
        self.assertEqual(len(lines), 4, out)  # header, rule, rigid, deformable
        self.assertEqual(lines[2], "| hoop | through_hoop | rigid | **yes** | **yes** | not run | "
                                   "twins 0 m apart | 3 |")
        self.assertEqual(lines[3], "| hoop | through_hoop | deformable | **yes**, 9.39 deg | "
                                   "**no**, 4.2 deg | not run | h = 0.0025 s, baseline strays "
                                   "8.6 % | 70 |")

    def test_a_demonstration_without_a_predicate_shows_its_figure(self):
        d = os.path.join(self.dir, "star")
        write_report(d, {"outcomes": {"predicate": "none", "figure": "angle",
                                      "figure_against": "own_simulator", "runs": [
                                          outcome("deformable", "reference", None, 0.0),
                                          outcome("deformable", "adversarial", None, 41.9)]}})
        code, out, err = run(f"star={d}", f"--out={os.path.join(self.dir, 'table.md')}")
        self.assertEqual((code, out), (0, ""), err)
        with open(os.path.join(self.dir, "table.md")) as f:
            text = f.read()
        self.assertIn("| star | figure: angle (own_simulator) | deformable | 0 deg | 41.9 deg | "
                      "not run |", text)

    def assert_one_line_error(self, args, *needles):
        code, out, err = run(*args)
        self.assertEqual(code, 1, out)
        self.assertEqual(out, "")
        self.assertEqual(len(err.strip().splitlines()), 1, err)
        for needle in needles:
            self.assertIn(needle, err)

    def test_a_directory_without_a_report_is_named(self):
        missing = os.path.join(self.dir, "nowhere")
        self.assert_one_line_error([f"bin={missing}"], "bin", missing)

    def test_a_report_that_is_not_json_is_named(self):
        d = os.path.join(self.dir, "broken")
        os.makedirs(d)
        with open(os.path.join(d, "report.json"), "w") as f:
            f.write("{\"outcomes\": ")
        self.assert_one_line_error([f"x={d}"], os.path.join(d, "report.json"))

    def test_a_report_without_outcomes_is_not_a_demonstration(self):
        d = os.path.join(self.dir, "plain")
        write_report(d, {"time_step_s": 0.01})
        self.assert_one_line_error([f"ball={d}"], os.path.join(d, "report.json"), "outcomes")

    def test_a_run_without_simulator_or_object_is_named(self):
        d = os.path.join(self.dir, "odd")
        write_report(d, {"outcomes": {"predicate": "inside_box", "runs": [{"run": "rigid x"}]}})
        self.assert_one_line_error([f"odd={d}"], os.path.join(d, "report.json"), "simulator")

    def test_a_report_that_is_no_object_or_no_text_is_named(self):
        for name, content in (("list", b"[]"), ("null", b"null"), ("latin1", b"{\"a\": \"\xe9\"}")):
            d = os.path.join(self.dir, name)
            os.makedirs(d)
            with open(os.path.join(d, "report.json"), "wb") as f:
                f.write(content)
            self.assert_one_line_error([f"x={d}"], os.path.join(d, "report.json"))

    def test_an_out_file_that_cannot_be_written_is_named(self):
        d = os.path.join(self.dir, "hoop")
        write_report(d, {"outcomes": {"predicate": "through_hoop", "runs": []}})
        target = os.path.join(self.dir, "no", "such", "table.md")
        self.assert_one_line_error([f"hoop={d}", f"--out={target}"], target)

    def test_a_baseline_that_strays_past_its_path_is_in_percent_not_powers_of_ten(self):
        d = os.path.join(self.dir, "stack")
        write_report(d, {"outcomes": {"predicate": "stands", "runs": []},
                         "time_step_s": 0.001, "baseline_disagreement": 1.5})
        code, out, err = run(f"stack={d}")
        self.assertEqual(code, 0, err)
        self.assertIn("baseline strays 150 %", out)

    def test_unknown_arguments_and_no_demonstrations_are_refused(self):
        self.assert_one_line_error(["--bogus"], "--bogus")
        self.assert_one_line_error([], "no demonstrations")
        self.assert_one_line_error(["=dir"], "'=dir'")


if __name__ == "__main__":
    SCRIPT = os.path.join(sys.argv.pop(1), "scripts", "outcome_table.py")
    unittest.main(verbosity=2)
