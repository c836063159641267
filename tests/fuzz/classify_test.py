"""The fuzz harness's judge against outcomes written by hand: it must pass a clean refusal,
with what a failed run adds under it, and count every other shape as a defect; and the judges
of the families (families.py) must see a file a payload made, a result lost, a victim changed."""
import json
import os
import shutil
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import classify as c  # noqa: E402
from classify import classify  # noqa: E402

ERROR = "hydrosoft: error: deck.yaml: step 1: did not converge (line 3)"
NOTHING_KEPT = "  no step had converged: nothing was kept"
KEPT = '  the 2 converged output steps are in out/ (summary.json: "status": "failed")'
CHECKPOINT_KEPT = '  a checkpoint to restart from is in out/ (without a summary.json)'


def judge(returncode, *lines, real_run=True):
    return classify(returncode, "\n".join(lines) + "\n", ["deck.yaml"], real_run, None)[0]


class Classify(unittest.TestCase):
    def test_one_error_line_naming_the_file_is_a_refusal(self):
        self.assertEqual(judge(2, ERROR, real_run=False), "rejected")
        self.assertEqual(judge(2, "hydrosoft: warning: mesh in mm", ERROR), "rejected")

    def test_a_failed_run_may_say_what_it_kept(self):
        self.assertEqual(judge(3, ERROR, NOTHING_KEPT), "rejected")
        self.assertEqual(judge(3, "hydrosoft: warning: mesh in mm", ERROR, KEPT), "rejected")
        self.assertEqual(judge(3, ERROR, CHECKPOINT_KEPT), "rejected")

    def test_any_other_second_line_is_a_defect(self):
        self.assertEqual(judge(3, ERROR, "  something else"), "defect")
        self.assertEqual(judge(3, ERROR, NOTHING_KEPT, NOTHING_KEPT), "defect")
        self.assertEqual(judge(3, NOTHING_KEPT, ERROR), "defect")
        # Only a real run fails with exit 3 and says what it kept.
        self.assertEqual(judge(2, ERROR, NOTHING_KEPT), "defect")
        self.assertEqual(judge(3, ERROR, NOTHING_KEPT, real_run=False), "defect")

    def test_dumps_signals_and_foreign_messages_are_defects(self):
        self.assertEqual(judge(-11), "defect")
        self.assertEqual(judge(2, ERROR, "[0]PETSC ERROR: something"), "defect")
        self.assertEqual(judge(4, ERROR), "defect")
        self.assertEqual(judge(2, "hydrosoft: error: other.yaml: x: y"), "defect")
        self.assertEqual(judge(2, ERROR, ERROR), "defect")

    def test_a_library_exception_is_not_a_reason(self):
        self.assertEqual(judge(2, "hydrosoft: error: [json.exception.out_of_range.403] key 'steps' not found"), "defect")
        self.assertEqual(judge(2, "hydrosoft: error: deck.yaml: std::bad_alloc"), "defect")

    def test_a_restart_or_an_output_folder_names_its_file(self):
        self.assertTrue(c.names_a_file("--restart: /w/run/ckpt/checkpoint.h5: no /node_ids", ["checkpoint.h5"]))
        self.assertTrue(c.names_a_file("output folder 'disk/results': another run is writing it", ["results"]))
        self.assertTrue(c.names_a_file("disk/results.partial/deck.h5: cannot write", ["results.partial"]))
        self.assertFalse(c.names_a_file("--restart: cannot read", ["checkpoint.h5"]))
        self.assertFalse(c.names_a_file("output folder 'other': x", ["results"]))


BANNER = """--------------------------------------------------------------------------
Primary job  terminated normally, but 1 process returned
a non-zero exit code. Per user-direction, the job has been aborted.
--------------------------------------------------------------------------"""
SIGNALLED = """--------------------------------------------------------------------------
mpiexec noticed that process rank 1 with PID 0 on node vm exited on signal 11 (Segmentation fault).
--------------------------------------------------------------------------"""


class Launcher(unittest.TestCase):
    def test_the_launchers_banner_is_its_own_but_a_rank_signal_is_a_defect(self):
        self.assertEqual(c.classify_ranks(2, ERROR + "\n" + BANNER, ["deck.yaml"], False, None, 2)[0], "rejected")
        self.assertEqual(c.classify_ranks(2, ERROR + "\n" + BANNER, ["deck.yaml"], False, None, 1)[0], "defect")
        self.assertEqual(c.classify_ranks(2, ERROR + "\n" + SIGNALLED, ["deck.yaml"], False, None, 2)[0], "defect")


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


def whole_result(folder, status, outputs, **extra):
    """A results folder as hydrosoft leaves it, without its .h5: summary.json and the .xmf."""
    write(os.path.join(folder, ".hydrosoft_output"), "Written by hydrosoft.\n")
    write(os.path.join(folder, "summary.json"), json.dumps(dict(status=status, outputs=outputs, **extra)))
    grids = "".join(f'<Grid Name="step_{k}" GridType="Uniform"></Grid>' for k in range(outputs))
    write(os.path.join(folder, "deck.xmf"), f'<Xdmf><Grid Name="deck">{grids}</Grid></Xdmf>')


class Families(unittest.TestCase):
    def setUp(self):
        self.root = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, self.root)

    def test_a_payloads_file_reached_the_system_and_any_other_was_left(self):
        before = c.snapshot(self.root)
        self.assertEqual(c.new_files_defect(self.root, before, lambda p: False), "")
        write(os.path.join(self.root, "run", "results", "x"), "")
        self.assertEqual(c.new_files_defect(self.root, before, lambda p: p.startswith("run")), "")
        write(os.path.join(self.root, "run", "helper.txt"), "")
        self.assertIn("left a file", c.new_files_defect(self.root, before, lambda p: p.startswith("run/results")))
        write(os.path.join(self.root, "outside", "MARKER_sys_1"), "")
        self.assertIn("reached the system", c.new_files_defect(self.root, before, lambda p: False))

    def test_a_full_disk_must_leave_the_earlier_result_and_no_partial(self):
        disk = os.path.join(self.root, "disk")
        whole_result(os.path.join(disk, "results"), "ok", 1)
        earlier = c.tree_digest(os.path.join(disk, "results"))
        refused = "hydrosoft: error: disk/results.partial/deck.h5: cannot write: No space left on device\n"
        self.assertEqual(c.judge_full_disk(2, refused, 1, disk, "results", earlier, False)[0], "rejected")
        self.assertEqual(c.judge_full_disk(None, "", 1, disk, "results", earlier, True)[0], "defect")
        os.makedirs(os.path.join(disk, "results.partial"))
        self.assertIn(".partial", c.judge_full_disk(2, refused, 1, disk, "results", earlier, False)[1])
        os.rmdir(os.path.join(disk, "results.partial"))
        write(os.path.join(disk, "results", "summary.json"), "{")
        self.assertIn("lost data", c.judge_full_disk(2, refused, 1, disk, "results", earlier, False)[1])

    def test_an_interactive_run_keeps_the_steps_it_answered(self):
        answers = ['{"answer": {}, "line": 1}', '{"error": "bad", "line": 2}']
        self.assertIn("lost data", c.judge_interactive(0, "", answers, 2, True, self.root, "results", 1, False)[1])
        whole_result(os.path.join(self.root, "results"), "ok", 5, targets=[{}],
                     input={"lines": 2, "answered": 1, "rejected": 1})
        self.assertEqual(c.judge_interactive(0, "", answers, 2, False, self.root, "results", 1, False)[0], "accepted")
        self.assertEqual(c.judge_interactive(-13, "", answers, 2, True, self.root, "results", 1, False)[0], "defect")
        self.assertEqual(c.judge_interactive(None, "", answers, 2, True, self.root, "results", 1, True)[0], "defect")
        # A client that read to the end must have one answer per line.
        self.assertEqual(c.judge_interactive(0, "", answers, 3, False, self.root, "results", 1, False)[0], "defect")
        swapped = [answers[1].replace('"line": 2', '"line": 1'), answers[0]]
        self.assertEqual(c.judge_interactive(0, "", swapped, 2, False, self.root, "results", 1, False)[0], "defect")

    def test_a_victim_behind_a_link_must_stay_as_it_was(self):
        victim = os.path.join(self.root, "victim.txt")
        write(victim, "not the run's\n")
        victims = {victim: c.tree_digest(victim)}
        whole_result(os.path.join(self.root, "results"), "ok", 1, deck="deck.yaml")
        runs = [("deck", 0, "", "results", 1, False)]
        self.assertEqual(c.judge_lock(runs, self.root, victims, None)[0], "accepted")
        self.assertIn("holds the result of", c.judge_lock([("other",) + runs[0][1:]], self.root, victims, None)[1])
        write(victim, "process 42 on host vm\n")
        self.assertIn("wrote through a link", c.judge_lock(runs, self.root, victims, None)[1])


if __name__ == "__main__":
    unittest.main()
