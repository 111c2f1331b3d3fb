#!/usr/bin/env python3
"""The helper scripts' command lines: a wrong argument is a one-line error and a non-zero exit,
not a silent default or a traceback (scripts/fit_bat_profile.py, scripts/mutation_check.py).

Run by ctest (tests/CMakeLists.txt) as `python3 tests/scripts/test_script_arguments.py SOURCE_DIR`.
"""
import os
import subprocess
import sys
import tempfile
import unittest

SOURCE = None  # set from argv in __main__


def run(script, *args):
    p = subprocess.run([sys.executable, os.path.join(SOURCE, "scripts", script), *args],
                       capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


class FitBatProfile(unittest.TestCase):
    def test_no_arguments_fits_the_polyhedron_and_four_losses_the_mesh(self):
        for args in ([], ["-0.01745", "-0.01557", "-0.01488", "-0.03055"]):
            code, out, err = run("fit_bat_profile.py", *args)
            self.assertEqual(code, 0, err)
            self.assertIn("profile (z, r):", out)

    def test_a_wrong_count_or_value_is_one_line(self):
        for args, says in ((["-0.01745"], "not 1"),
                           (["-0.01745", "-0.01557", "-0.01488"], "not 3"),
                           (["a", "0", "0", "0"], "not a number"),
                           (["nan", "0", "0", "0"], "finite and above -1"),
                           (["-1", "0", "0", "0"], "finite and above -1")):
            code, out, err = run("fit_bat_profile.py", *args)
            self.assertNotEqual(code, 0, args)
            self.assertIn(says, err, args)
            self.assertEqual(err.count("\n"), 1, err)
            self.assertEqual(out, "", args)


class MutationCheck(unittest.TestCase):
    def test_bad_count_jobs_and_report_folder_are_one_line(self):
        with tempfile.TemporaryDirectory() as tmp:
            missing = os.path.join(tmp, "no_such_folder", "report.md")
            for args, says in ((["--list", "--count", "-1"], "--count must be at least 1"),
                               (["--list", "--count", "0"], "--count must be at least 1"),
                               (["--list", "--jobs", "0"], "--jobs must be at least 1"),
                               (["--list", "--report", missing], "no folder")):
                code, out, err = run("mutation_check.py", *args)
                self.assertNotEqual(code, 0, args)
                self.assertIn(says, err, args)
                self.assertEqual(err.count("\n"), 1, err)


if __name__ == "__main__":
    SOURCE = sys.argv.pop(1)
    unittest.main()
