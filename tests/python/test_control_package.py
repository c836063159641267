#!/usr/bin/python3
"""The Python control package (python/hydrosoft_control) against real runs of the coarse
hydraulic finger: answers reach the target, a refused line raises and the scene goes on, the
answers are those summary.json records, 2 ranks answer as 1, a scene that cannot start
says why, a killed scene is kept as failed on 1 and 2 ranks, a target of 2 numbers is refused
and the scene goes on, a temporary output folder is removed when the scene ends (closed,
an error in its block, stopped, or its interpreter's exit), and an output folder whose path
holds ' #' is written there; a contact-force effector's answer is a force.

    HYDROSOFT=build/bin/hydrosoft /usr/bin/python3 tests/python/test_control_package.py
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "python"))
from hydrosoft_control import Scene, SceneError, TargetRefused  # noqa: E402

DECK = os.path.join(ROOT, "input", "finger_hydraulic.yaml")
# The coarse finger in its compressible material, as the C++ tests of mechanisms run it
# (tests/pinned_decks.hpp).
COARSE = ["mesh.parameters.h=0.006", "materials[0].E=2.0e5", "materials[0].nu=0.45",
          "control.actuators[0].max_pressure=30000"]
LOW, HIGH = [0.09, 0.0, -0.012], [0.09, 0.0, -0.008]  # the deck's targets 0 and 4 (z steered)


class ControlPackage(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="hydrosoft_python_test_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def scene(self, name, ranks=1, deck=DECK, overrides=COARSE):
        return Scene(deck, ranks=ranks, overrides=overrides,
                     output_folder=os.path.join(self.tmp, name))

    def test_answers_reach_the_targets_and_a_refused_line_changes_nothing(self):
        with self.scene("one") as scene:
            low = scene.reach(LOW)
            with self.assertRaises(TargetRefused) as refused:
                scene.send_line("0.09 abc -0.01")
            # Before, two numbers raised a bare ValueError: a client catching TargetRefused
            # to go on lost its scene.
            with self.assertRaises(TargetRefused) as short:
                scene.reach(HIGH[::2])
            high = scene.reach(HIGH, effector="tip")
        self.assertEqual(refused.exception.line, 2)
        self.assertIn("abc", str(refused.exception))
        self.assertIn("3 numbers", str(short.exception))
        self.assertIsNone(short.exception.line)  # never sent: the input's lines are 3
        for answer, target in ((low, LOW), (high, HIGH)):
            self.assertEqual(answer.effector, "tip")
            np.testing.assert_array_equal(answer.target, target)
            self.assertLess(abs(answer.reached[2] - target[2]), 5e-5)  # z is steered
            self.assertAlmostEqual(answer.error_m, abs(answer.reached[2] - target[2]), delta=1e-15)
            self.assertTrue(0 < answer.actuation[0] <= 30000)
        self.assertLess(low.actuation[0], high.actuation[0])  # higher takes more pressure
        self.assertEqual((low.line, high.line), (1, 3))
        summary = scene.summary
        self.assertEqual(summary["input"], {"lines": 3, "answered": 2, "rejected": 1,
                                            "failed": 0, "end": "end of input", "undelivered": 0})
        for answer, entry in zip((low, high), summary["targets"]):
            np.testing.assert_array_equal(answer.reached, entry["reached"])
            np.testing.assert_array_equal(answer.actuation, entry["actuation"])
            self.assertEqual(answer.line, entry["line"])

    def test_a_grasp_force_is_answered_in_newtons(self):
        # A contact-force effector of input/gripper_grasp.yaml (coarse): the left finger
        # closes on the ball and presses it with 0.04 N; its answer is a force.
        deck = os.path.join(ROOT, "input", "gripper_grasp.yaml")
        with self.scene("grasp", deck=deck, overrides=COARSE) as scene:
            grasp = scene.reach([0.0, -0.04, 0.0], effector="grip_left")
        self.assertIsNone(grasp.error_m)
        self.assertLess(grasp.error_N, 1e-5)
        self.assertAlmostEqual(grasp.error_N, abs(grasp.reached[1] + 0.04), delta=1e-15)
        self.assertIn(" N", repr(grasp))
        ball = grasp.raw["contact"]["obstacles"][0]["force_N"]
        np.testing.assert_array_equal(grasp.reached, ball)  # the right finger is away
        self.assertEqual(grasp.actuation[1], 0.0)

    def test_two_ranks_answer_as_one(self):
        with self.scene("np1") as one:
            a = one.reach(LOW)
        with self.scene("np2", ranks=2) as two:
            b = two.reach(LOW)
        np.testing.assert_allclose(b.reached, a.reached, rtol=0, atol=1e-9)
        np.testing.assert_allclose(b.actuation, a.actuation, rtol=1e-7)

    def test_a_scene_that_cannot_start_says_why(self):
        with self.assertRaises(SceneError) as missing:
            self.scene("missing", deck=os.path.join(self.tmp, "no_such.yaml"))
        self.assertIn("no_such.yaml", str(missing.exception))
        scene = self.scene("bad", overrides=COARSE + ["control.steps_per_target=0"])
        with self.assertRaises(SceneError) as bad:
            scene.reach(LOW)
        self.assertIn("control.steps_per_target", str(bad.exception))
        scene.kill()


    def test_a_killed_scene_is_kept_as_failed(self):
        # Before, on 2 ranks the SIGTERM went to mpirun, which first closed the ranks' input:
        # the session ended as if its client had ended it and was kept as a good result.
        for ranks in (1, 2):
            scene = self.scene("killed%d" % ranks, ranks=ranks)
            scene.reach(LOW)
            scene.kill()
            self.assertEqual(scene._proc.returncode, 143, scene._messages())
            self.assertFalse(os.path.exists(scene.folder), ranks)
            with open(os.path.join(scene.folder + ".failed", "summary.json")) as f:
                summary = json.load(f)
            self.assertEqual(summary["status"], "failed")
            self.assertEqual(summary["reason"], "interrupted by SIGTERM")
            self.assertEqual(len(summary["targets"]), 1)

    def test_a_temporary_output_folder_goes_with_its_scene(self):
        # Before, every Scene() without output_folder left a hydrosoft_scene_* folder behind.
        env = dict(os.environ, TMPDIR=self.tmp)
        saved, tempfile.tempdir = tempfile.tempdir, self.tmp
        try:
            with Scene(DECK, overrides=COARSE) as scene:
                scene.reach(LOW)
                self.assertEqual(os.listdir(self.tmp), [os.path.basename(os.path.dirname(scene.folder))])
            self.assertEqual(scene.summary["status"], "ok")
            self.assertEqual(os.listdir(self.tmp), [])
            with self.assertRaises(KeyError):  # an error inside the block
                with Scene(DECK, overrides=COARSE) as scene:
                    scene.reach(LOW)
                    raise KeyError("the client's own error")
            self.assertEqual(os.listdir(self.tmp), [])
            with self.assertRaises(SceneError) as bad:  # a scene that stopped
                with Scene(DECK, overrides=COARSE + ["control.steps_per_target=0"]) as scene:
                    scene.reach(LOW)
            self.assertIn("control.steps_per_target", str(bad.exception))
            self.assertEqual(os.listdir(self.tmp), [])
            with Scene(DECK, overrides=COARSE, keep=True) as scene:
                scene.reach(LOW)
            self.assertTrue(os.path.isfile(os.path.join(scene.folder, "summary.json")))
            shutil.rmtree(os.path.dirname(scene.folder))
        finally:
            tempfile.tempdir = saved
        # A scene never closed, its interpreter exiting while the run waits for input.
        script = ("import sys; sys.path.insert(0, %r)\nfrom hydrosoft_control import Scene\n"
                  "scene = Scene(%r, overrides=%r)\nscene.reach(%r)\n"
                  % (os.path.join(ROOT, "python"), DECK, COARSE, LOW))
        subprocess.run([sys.executable, "-c", script], env=env, check=True, timeout=300)
        self.assertEqual(os.listdir(self.tmp), [])

    def test_an_output_folder_with_a_yaml_comment_in_its_path(self):
        # Before, the path was cut at " #" (a YAML comment): the results replaced "<tmp>/a".
        parent = os.path.join(self.tmp, "a #b")
        os.mkdir(parent)
        with Scene(DECK, overrides=COARSE, output_folder=os.path.join(parent, "run")) as scene:
            scene.reach(LOW)
        self.assertEqual(scene.summary["status"], "ok")
        self.assertEqual(sorted(os.listdir(self.tmp)), ["a #b"])
        self.assertTrue(os.path.isfile(os.path.join(parent, "run", "finger_hydraulic.h5")))


if __name__ == "__main__":
    unittest.main(verbosity=2)
