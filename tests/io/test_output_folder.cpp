// OutputFolder (staging, commit, clean-up, never deleting foreign folders or following links,
// one run at a time per folder), FolderLock, and the files written beside the .h5 (write_json,
// write_file_atomically, history.csv) when they find no room.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "../deck/temp_folder.hpp"
#include "common/error.hpp"
#include "file_size_limit.hpp"
#include "io/atomic_file.hpp"
#include "io/output.hpp"
#include "io/step_history.hpp"

namespace hs {
namespace {

namespace fs = std::filesystem;
using testing::TempFolder;

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path) << text; }

// A committed output folder holding result.txt = text, as a previous run leaves it.
void previous_run(const std::string& folder, const std::string& text) {
  OutputFolder out(folder);
  write_text(out.staging() + "/result.txt", text);
  out.commit();
}

TEST(OutputFolder, CommitMovesStagingToFinal) {
  TempFolder tmp;
  const std::string final = (tmp.path() / "results" / "run").string();
  OutputFolder out(final + "/");  // a trailing slash names the same folder
  EXPECT_EQ(out.final(), final);
  EXPECT_EQ(out.staging(), final + ".partial");
  EXPECT_TRUE(fs::is_directory(out.staging()));
  EXPECT_FALSE(fs::exists(final));  // nothing final before the commit
  write_text(out.staging() + "/result.txt", "new");
  out.commit();
  EXPECT_EQ(read_text(final + "/result.txt"), "new");
  EXPECT_FALSE(fs::exists(final + ".partial"));
}

TEST(OutputFolder, CommitReplacesAnOldFolder) {
  TempFolder tmp;
  const std::string final = (tmp.path() / "run").string();
  previous_run(final, "old");
  write_text(final + "/only_in_old.txt", "x");
  previous_run(final, "new");
  EXPECT_EQ(read_text(final + "/result.txt"), "new");
  EXPECT_FALSE(fs::exists(final + "/only_in_old.txt"));  // replaced, not merged
  EXPECT_FALSE(fs::exists(final + ".old"));
  EXPECT_FALSE(fs::exists(final + ".partial"));
}

// The commit swaps the new results and the old ones in one rename: a kill at any moment
// leaves one of them at <folder>. Seen from the parent folder: only the two names move, and
// the earlier result never goes through <folder>.old (the two-rename commit, where a kill
// between the renames left no <folder>).
TEST(OutputFolder, CommitExchangesTheFolders) {
  TempFolder tmp;
  const std::string final = (tmp.path() / "run").string();
  previous_run(final, "old");
  OutputFolder out(final);
  write_text(out.staging() + "/result.txt", "new");
  const int watch = inotify_init1(IN_NONBLOCK);
  ASSERT_GE(watch, 0);
  ASSERT_GE(inotify_add_watch(watch, tmp.path().c_str(), IN_MOVED_FROM | IN_MOVED_TO | IN_CREATE),
            0);
  out.commit();
  std::vector<std::string> names;
  alignas(inotify_event) char buffer[8192];
  for (ssize_t n; (n = read(watch, buffer, sizeof buffer)) > 0;)
    for (char* p = buffer; p < buffer + n;) {
      const auto* event = reinterpret_cast<const inotify_event*>(p);
      if (event->len > 0) names.emplace_back(event->name);
      p += sizeof(inotify_event) + event->len;
    }
  close(watch);
  for (const auto& name : names) EXPECT_NE(name, "run.old");
  EXPECT_FALSE(names.empty());  // the exchange itself is seen
  EXPECT_EQ(read_text(final + "/result.txt"), "new");
  EXPECT_FALSE(fs::exists(final + ".partial"));
}

TEST(OutputFolder, UncommittedRunLeavesTheOldFolderAlone) {
  TempFolder tmp;
  const std::string final = (tmp.path() / "run").string();
  previous_run(final, "old");
  try {
    OutputFolder out(final);
    write_text(out.staging() + "/result.txt", "half-written");
    throw SolveError("step 3: Newton did not converge");  // the run fails
  } catch (const SolveError&) {
  }
  EXPECT_FALSE(fs::exists(final + ".partial"));
  EXPECT_EQ(read_text(final + "/result.txt"), "old");
}

TEST(OutputFolder, AFailedRunKeepsItsStepsInFailedAndLeavesTheGoodFolderAlone) {
  TempFolder tmp;
  const std::string final = (tmp.path() / "run").string();
  previous_run(final, "good");
  {
    OutputFolder out(final);
    write_text(out.staging() + "/result.txt", "first failure");
    EXPECT_EQ(out.keep_failed(), final + ".failed");
  }  // the object's end deletes nothing once kept
  EXPECT_EQ(read_text(final + ".failed/result.txt"), "first failure");
  EXPECT_TRUE(fs::exists(final + ".failed/.hydrosoft_output"));
  EXPECT_EQ(read_text(final + "/result.txt"), "good");
  EXPECT_FALSE(fs::exists(final + ".partial"));
  {
    OutputFolder out(final);
    write_text(out.staging() + "/other.txt", "second failure");
    out.keep_failed();
  }
  // The earlier .failed was replaced, not merged.
  EXPECT_FALSE(fs::exists(final + ".failed/result.txt"));
  EXPECT_EQ(read_text(final + ".failed/other.txt"), "second failure");
  EXPECT_EQ(read_text(final + "/result.txt"), "good");
}

TEST(OutputFolder, AForeignFailedFolderIsRefusedBeforeTheRun) {
  TempFolder tmp;
  const std::string final = (tmp.path() / "run").string();
  fs::create_directories(final + ".failed");
  write_text(final + ".failed/notes.txt", "mine");
  EXPECT_NE(output_folder_problem(final).find("run.failed' exists and was not written by"),
            std::string::npos)
      << output_folder_problem(final);
  EXPECT_THROW(OutputFolder{final}, InputError);
  EXPECT_EQ(read_text(final + ".failed/notes.txt"), "mine");
}

TEST(OutputFolder, ClearsTheStagingFolderOfACrashedRun) {
  TempFolder tmp;
  const std::string final = (tmp.path() / "run").string();
  {
    OutputFolder crashed(final);
    write_text(crashed.staging() + "/stale.txt", "x");
    fs::copy(crashed.staging(), final + ".kept");  // what a killed process leaves behind
  }
  fs::rename(final + ".kept", final + ".partial");
  ASSERT_TRUE(fs::exists(final + ".partial/stale.txt"));
  OutputFolder out(final);
  EXPECT_FALSE(fs::exists(out.staging() + "/stale.txt"));
}

TEST(OutputFolder, NeverDeletesAFolderItDidNotWrite) {
  TempFolder tmp;
  const fs::path mine = tmp.path() / "thesis";
  fs::create_directories(mine);
  write_text(mine / "chapter1.tex", "precious");
  EXPECT_THROW(OutputFolder{mine.string()}, InputError);
  EXPECT_NE(output_folder_problem(mine.string()).find("was not written by hydrosoft"),
            std::string::npos);
  EXPECT_EQ(read_text(mine / "chapter1.tex"), "precious");
  EXPECT_FALSE(fs::exists(mine.string() + ".partial"));
  // A foreign "<folder>.partial" is just as safe.
  fs::create_directories(tmp.path() / "run.partial");
  write_text(tmp.path() / "run.partial" / "notes.txt", "mine");
  EXPECT_THROW(OutputFolder{(tmp.path() / "run").string()}, InputError);
  EXPECT_EQ(read_text(tmp.path() / "run.partial" / "notes.txt"), "mine");
  // An empty folder may be used.
  fs::create_directories(tmp.path() / "empty");
  EXPECT_EQ(output_folder_problem((tmp.path() / "empty").string()), "");
  EXPECT_NE(output_folder_problem("."), "");
  EXPECT_NE(output_folder_problem("out/.."), "");
}

// The message of the InputError that opening `folder` throws, or "" if it opens.
std::string refusal(const std::string& folder) {
  try {
    OutputFolder second(folder);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(OutputFolder, ASecondRunOnTheSameFolderStopsAtOnceAndDeletesNothing) {
  TempFolder tmp;
  const std::string final = (tmp.path() / "run").string();
  previous_run(final, "old");
  OutputFolder first(final);
  write_text(first.staging() + "/result.txt", "first");
  EXPECT_EQ(read_text(final + ".lock").find("process " + std::to_string(getpid())), 0u);
  const std::string message = refusal(final + "/");  // the same folder, spelled otherwise
  EXPECT_NE(message.find("output folder '" + final + "': another run is writing it (process " +
                         std::to_string(getpid())),
            std::string::npos)
      << message;
  // The first run's staging folder and the old results are untouched, and it commits.
  EXPECT_EQ(read_text(first.staging() + "/result.txt"), "first");
  EXPECT_EQ(read_text(final + "/result.txt"), "old");
  first.commit();
  EXPECT_EQ(read_text(final + "/result.txt"), "first");
}

TEST(OutputFolder, TheLockIsReleasedWithTheRunCommittedOrNot) {
  TempFolder tmp;
  const std::string final = (tmp.path() / "run").string();
  previous_run(final, "one");
  EXPECT_FALSE(fs::exists(final + ".lock"));  // removed on release
  { OutputFolder failed(final); }             // a run that fails
  EXPECT_FALSE(fs::exists(final + ".lock"));
  EXPECT_EQ(refusal(final), "");
  // Other folders beside it are not locked by it.
  OutputFolder a(final);
  EXPECT_EQ(refusal((tmp.path() / "run2").string()), "");
}

TEST(FolderLock, ALockLeftByAKilledRunDoesNotBlock) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "run").string();
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {  // a run that takes the lock and is killed while it holds it
    FolderLock lock(folder);
    if (write(ready[1], "1", 1) != 1) _exit(1);
    pause();
    _exit(0);
  }
  char c = 0;
  ASSERT_EQ(read(ready[0], &c, 1), 1);
  EXPECT_THROW(FolderLock{folder}, InputError);  // held by the child
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  close(ready[0]);
  close(ready[1]);
  EXPECT_TRUE(fs::exists(folder + ".lock"));  // its file is left behind ...
  FolderLock next(folder);                    // ... and taken over at once
  EXPECT_EQ(read_text(folder + ".lock").find("process " + std::to_string(getpid())), 0u);
}

TEST(FolderLock, AFolderThatCannotHoldALockSaysWhy) {
  try {
    FolderLock lock("/proc/hydrosoft_no_such_folder/run");
    ADD_FAILURE() << "locked in /proc";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot create its lock file"), std::string::npos)
        << e.what();
  }
}

// A link named <folder>.lock would have the run truncate the file it names and write its
// process into it: refused, naming the lock, the file it names untouched (with O_NOFOLLOW).
TEST(FolderLock, ALinkedOrHardLinkedLockFileIsRefusedAndWhatItNamesUntouched) {
  TempFolder tmp;
  const std::string folder = (tmp.path() / "run").string();
  const fs::path victim = tmp.path() / "notes.txt";
  write_text(victim, "precious");
  fs::create_symlink(victim, folder + ".lock");
  try {
    FolderLock lock(folder);
    ADD_FAILURE() << "locked through a link";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("its lock file '" + folder + ".lock' is a symbolic link"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(read_text(victim), "precious");
  EXPECT_TRUE(fs::is_symlink(folder + ".lock"));  // not removed either
  EXPECT_NE(output_folder_problem(folder).find("'" + folder + ".lock' is a symbolic link"),
            std::string::npos)
      << output_folder_problem(folder);
  fs::remove(folder + ".lock");
  fs::create_hard_link(victim, folder + ".lock");
  EXPECT_THROW(FolderLock{folder}, InputError);
  EXPECT_EQ(read_text(victim), "precious");
}

// Each refusal below is said by output_folder_problem (so by the deck's check, before any
// work) and enforced by the OutputFolder itself; nothing it names is touched.
void expect_refused(const std::string& folder, const std::string& reason) {
  EXPECT_NE(output_folder_problem(folder).find(reason), std::string::npos)
      << folder << ": " << output_folder_problem(folder);
  try {
    OutputFolder out(folder);
    ADD_FAILURE() << folder << " accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
  }
}

// The commit renames the staging folder over <folder>: a link there would be replaced by a
// real folder and the folder it names left with the old results. The staging folders are
// deleted and renamed: never through a link.
TEST(OutputFolder, LinkedFoldersAreRefused) {
  TempFolder tmp;
  const fs::path target = tmp.path() / "elsewhere";
  fs::create_directories(target);
  write_text(target / "result.txt", "theirs");
  const std::string final = (tmp.path() / "run").string();
  fs::create_symlink(target, final);
  expect_refused(final, "'" + final + "' is a symbolic link (to '" + target.string() + "')");
  fs::remove(final);
  for (const std::string suffix : {".partial", ".failed", ".old"}) {
    fs::create_symlink(target, final + suffix);
    expect_refused(final, "'" + final + suffix + "' is a symbolic link");
    fs::remove(final + suffix);
  }
  EXPECT_EQ(read_text(target / "result.txt"), "theirs");
  EXPECT_EQ(fs::directory_iterator(target)->path().filename(), "result.txt");
  EXPECT_EQ(output_folder_problem(final), "");
  // A link above the folder is followed as any path is.
  fs::create_symlink(target, tmp.path() / "link");
  previous_run((tmp.path() / "link" / "run").string(), "through the link");
  EXPECT_EQ(read_text(target / "run" / "result.txt"), "through the link");
}

// A run on "<folder>.partial" would replace the staging folder of a run on <folder> (which
// then fails) and the run on <folder> would later delete it as a crashed run's leftover: the
// names of a folder's family are not output folders.
TEST(OutputFolder, TheNamesOfAnotherFoldersRunAreRefused) {
  TempFolder tmp;
  const std::string head = (tmp.path() / "fa").string();
  OutputFolder running(head);
  write_text(running.staging() + "/step.txt", "the running one's");
  expect_refused(head + ".partial",
                 "a name ending in '.partial' is that of the staging folder of '" + head + "'");
  expect_refused(head + ".failed/", "a name ending in '.failed'");
  expect_refused(head + ".old", "a name ending in '.old'");
  expect_refused(head + ".lock", "a name ending in '.lock'");
  EXPECT_EQ(read_text(running.staging() + "/step.txt"), "the running one's");
  running.commit();
  EXPECT_EQ(read_text(head + "/step.txt"), "the running one's");
  EXPECT_EQ(output_folder_problem(head + ".partial.results"), "");  // only at the end
}

// Before: std::filesystem's "File name too long" escaped as a raw exception.
TEST(OutputFolder, NamesAndPathsTooLongForARunAreRefusedWithTheReason) {
  TempFolder tmp;
  const std::string name_300 = (tmp.path() / std::string(300, 'a')).string();
  EXPECT_NE(output_folder_problem(name_300).find("the folder's name is 300 characters long"),
            std::string::npos)
      << output_folder_problem(name_300);
  // Fine alone, but not with ".partial" (255 characters at most).
  const std::string name_250 = (tmp.path() / std::string(250, 'c')).string();
  EXPECT_NE(output_folder_problem(name_250).find("with '.partial' added it would exceed the 255"),
            std::string::npos);
  std::string deep = tmp.path().string();
  while (deep.size() < 5000) deep += "/" + std::string(200, 'b');
  EXPECT_NE(output_folder_problem(deep).find("characters long: with the files a run writes in it"),
            std::string::npos)
      << output_folder_problem(deep).substr(0, 200);
  EXPECT_THROW(OutputFolder{deep}, InputError);
  EXPECT_EQ(output_folder_problem((tmp.path() / std::string(200, 'd')).string()), "");
}

// On a full device (/dev/full): the reason is said, the earlier file stays whole and no
// .tmp is left.
TEST(WriteFileAtomically, AFullDeviceLeavesTheEarlierFileAndSaysWhy) {
  TempFolder tmp;
  const std::string path = (tmp.path() / "case.xmf").string();
  write_file_atomically(path, "earlier");
  fs::create_symlink("/dev/full", path + ".tmp");
  try {
    write_file_atomically(path, "later");
    ADD_FAILURE() << "written to /dev/full";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path + ": cannot write the file: No space left on device");
  }
  EXPECT_EQ(read_text(path), "earlier");
  EXPECT_FALSE(fs::exists(fs::symlink_status(path + ".tmp")));
}

// A row that does not fit is taken back: history.csv never ends in half a row.
TEST(StepHistory, ARowThatFindsNoRoomLeavesTheRowsBefore) {
  TempFolder tmp;
  const std::string csv = (tmp.path() / "history.csv").string();
  StepHistory history;
  HistoryRow row;
  row.add_count("step", 0);
  row.add("load_factor", 0.5);
  history.append(row, csv);
  const std::string before = read_text(csv);
  EXPECT_EQ(before, "step,load_factor\n0,0.5\n");
  try {
    const testing::FileSizeLimit limit(before.size() + 4);  // "1,0." fits, the rest not
    row.cells[0].value = 1;
    row.cells[1].value = 0.123456789;
    history.append(row, csv);
    ADD_FAILURE() << "appended past the limit";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), csv + ": cannot write: File too large");
  }
  EXPECT_EQ(read_text(csv), before);
  EXPECT_EQ(history.rows(), 2u);  // kept in memory: the .h5's /history has it
}

TEST(WriteJson, WritesPrettyJsonThatReadsBack) {
  TempFolder tmp;
  const std::string path = (tmp.path() / "summary.json").string();
  const nlohmann::json summary = {
      {"ranks", 2},
      {"dofs", 12345},
      {"time_s", {{"total", 1.25}, {"assembly", 0.5}, {"solve", 0.625}}},
      {"error", {{"l2_relative", 3.2e-5}}}};
  write_json(path, summary);
  const std::string text = read_text(path);
  EXPECT_EQ(nlohmann::json::parse(text), summary);
  EXPECT_EQ(text, summary.dump(2) + "\n");
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

TEST(WriteJson, RefusesNonFiniteNumbers) {
  TempFolder tmp;
  const std::string path = (tmp.path() / "summary.json").string();
  nlohmann::json summary = {{"time_s", {{"total", NAN}}}, {"steps", 3}};
  try {
    write_json(path, summary);
    ADD_FAILURE() << "NaN written";
  } catch (const SolveError& e) {
    EXPECT_EQ(std::string(e.what()).find(path + ": time_s.total is not finite"), 0u) << e.what();
  }
  summary = {{"history", {1.0, 2.0, INFINITY}}};
  EXPECT_THROW(write_json(path, summary), SolveError);
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace hs
