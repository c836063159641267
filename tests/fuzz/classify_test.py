"""The fuzz harness's judge against outcomes written by hand: it must pass a clean refusal,
with what a failed run adds under it, and count every other shape as a defect."""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
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


if __name__ == "__main__":
    unittest.main()
