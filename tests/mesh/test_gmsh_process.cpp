// gmsh's own process (src/mesh/gmsh_process.hpp, docs/reliability.md, "gmsh runs confined"):
// what a .geo does past the checks before gmsh cannot start a program or write a file; gmsh's
// crashes, errors and memory exhaustion come back as input errors naming the file; a SIGTERM
// ends the meshing at once; the mesh comes back whole, and damaged bytes never pass as a mesh.
#include <gmsh.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <thread>

#include "common/confinement.hpp"
#include "common/interrupt.hpp"
#include "mesh/gmsh_model.hpp"
#include "mesh/gmsh_process.hpp"
#include "mesh/mesh_wire.hpp"
#include "mesh_test_util.hpp"

namespace hs::test {
namespace {

namespace fs = std::filesystem;

// What confine_process achieves on this machine, found in a throw-away child.
Confinement confinement_here() {
  int fds[2];
  if (pipe(fds) != 0) return {};
  const pid_t child = fork();
  if (child == 0) {
    const Confinement c = confine_process();
    if (write(fds[1], &c, sizeof c) != sizeof c) _exit(1);
    _exit(0);
  }
  close(fds[1]);
  Confinement c;
  if (read(fds[0], &c, sizeof c) != sizeof c) c = {};
  close(fds[0]);
  waitpid(child, nullptr, 0);
  return c;
}

// gmsh meshes `geo` as it is, without the checks that come before gmsh in load_mesh.
Mesh mesh_unchecked(const std::string& geo) {
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::open(geo);
  gmsh::model::mesh::generate(3);
  Mesh m = mesh_from_gmsh_model(geo, 1);
  gmsh::finalize();
  return m;
}

std::string cube_after(const TempDir& dir, const std::string& name, const std::string& before) {
  const std::string path = dir.file(name);
  std::ofstream(path) << before
                      << "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 1, 1, 1};\n"
                         "Physical Volume(\"body\") = {1};\nMesh.MeshSizeMax = 0.5;\n";
  return path;
}

TEST(GmshProcess, ConfinedItCannotStartAProgram) {
  const Confinement here = confinement_here();
  if (!here.seccomp && here.landlock_abi == 0) GTEST_SKIP() << "no seccomp and no Landlock here";
  TempDir dir;
  const std::string marker = dir.file("ran");
  const std::string geo = cube_after(dir, "shell.geo", "SystemCall \"touch " + marker + "\";\n");
  GmshProcess open;
  open.confined = false;
  EXPECT_GT(run_gmsh_process(
                geo, [&] { return mesh_unchecked(geo); }, open)
                .num_tets(),
            0);
  ASSERT_TRUE(fs::exists(marker)) << "the case does not run a command when it is not confined";
  fs::remove(marker);
  // gmsh finds no shell to run the command in, and says so.
  expect_input_error([&] { run_gmsh_process(geo, [&] { return mesh_unchecked(geo); }); },
                     {geo + ": gmsh: ", "/bin/sh"});
  EXPECT_FALSE(fs::exists(marker));
}

TEST(GmshProcess, ConfinedItCannotWriteAFile) {
  const Confinement here = confinement_here();
  if (here.landlock_abi == 0) GTEST_SKIP() << "no Landlock here: only non-empty writes stop";
  TempDir dir;
  const std::string written = dir.file("written.txt"), existing = dir.file("existing.txt");
  std::ofstream(existing) << "keep me\n";
  const std::string geo = cube_after(dir, "write.geo",
                                     "Printf(\"x\") > \"" + written +
                                         "\";\n"
                                         "Printf(\"y\") > \"" +
                                         existing + "\";\n");
  GmshProcess open;
  open.confined = false;
  run_gmsh_process(
      geo, [&] { return mesh_unchecked(geo); }, open);
  ASSERT_TRUE(fs::exists(written)) << "the case writes nothing when it is not confined";
  fs::remove(written);
  std::ofstream(existing) << "keep me\n";
  try {
    run_gmsh_process(geo, [&] { return mesh_unchecked(geo); });
  } catch (const InputError&) {  // gmsh may call the failed write an error; either way:
  }
  EXPECT_FALSE(fs::exists(written));
  std::ifstream in(existing);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "keep me");
}

TEST(GmshProcess, ErrorsComeBackAsTheyWereThrown) {
  const auto throws = [](auto error) { return [error]() -> Mesh { throw error; }; };
  expect_input_error([&] { run_gmsh_process("f.geo", throws(InputError("f.geo: bad line"))); },
                     {"f.geo: bad line"});
  try {
    run_gmsh_process("f.geo", throws(std::runtime_error("not input")));
    ADD_FAILURE() << "no error";
  } catch (const InputError&) {
    ADD_FAILURE() << "an input error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "not input");
  }
  expect_input_error([&] { run_gmsh_process("f.msh", throws(std::bad_alloc())); },
                     {"f.msh: gmsh ran out of memory reading it"});
  // An exception thrown where nothing can catch it (gmsh's parallel regions).
  expect_input_error(
      [&] {
        run_gmsh_process("f.geo", []() -> Mesh {
          std::thread([] { throw std::string("meshing failed"); }).join();
          return {};
        });
      },
      {"f.geo: gmsh: meshing failed"});
}

TEST(GmshProcess, ACrashIsAnInputErrorNamingTheFile) {
  expect_input_error(
      [&] {
        run_gmsh_process("crash.msh", []() -> Mesh {
          raise(SIGSEGV);
          return {};
        });
      },
      {"crash.msh: gmsh died of signal 11 (Segmentation fault) while reading it"});
  expect_input_error([&] { run_gmsh_process("exit.geo", []() -> Mesh { std::exit(0); }); },
                     {"exit.geo: gmsh was told to exit before reading it to the end"});
}

// A heap corruption's abort, or gmsh's own error line, printed beside the run's one-line error.
TEST(GmshProcess, ItPrintsNothing) {
  ::testing::internal::CaptureStderr();
  ::testing::internal::CaptureStdout();
  expect_input_error(
      [&] {
        run_gmsh_process("noisy.geo", []() -> Mesh {
          std::fprintf(stderr, "free(): invalid pointer\n");
          std::printf("Error   : boom\n");
          std::fflush(nullptr);
          std::abort();
        });
      },
      {"noisy.geo: gmsh died of signal 6"});
  EXPECT_EQ(::testing::internal::GetCapturedStdout(), "");
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

TEST(GmshProcess, ItReadsNothingFromStandardInput) {
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const int saved = dup(0);
  dup2(fds[0], 0);
  ASSERT_EQ(write(fds[1], "0.09 0 -0.012\n", 14), 14);
  close(fds[1]);
  std::string seen = "not run";
  try {
    run_gmsh_process("f.geo", []() -> Mesh {
      std::string line;
      std::getline(std::cin, line);
      throw InputError("read '" + line + "'");
    });
  } catch (const InputError& e) {
    seen = e.what();
  }
  char left[32] = {};
  const ssize_t n = read(0, left, sizeof left);
  dup2(saved, 0);
  close(saved);
  close(fds[0]);
  EXPECT_EQ(seen, "read ''");
  EXPECT_EQ(std::string(left, n > 0 ? n : 0), "0.09 0 -0.012\n");
}

// SIGTERM (a cluster's time limit) used to wait for the meshing to end. In a child of the test,
// with the run's handlers: a .geo that loops for minutes stops within a second, and gmsh's
// process is gone.
TEST(GmshProcess, SigtermEndsTheMeshingAtOnce) {
  TempDir dir;
  const std::string geo = cube_after(dir, "loop.geo", "For i In {1:2e9}\nEndFor\n");
  const std::string pid_file = dir.file("gmsh.pid");
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    install_interrupt_handlers();
    GmshProcess open;
    open.confined = false;  // to leave its process id behind
    try {
      run_gmsh_process(
          geo,
          [&] {
            std::ofstream(pid_file) << getpid() << "\n";
            return mesh_unchecked(geo);
          },
          open);
    } catch (const Interrupted& e) {
      _exit(e.signal == SIGTERM ? 43 : 44);
    } catch (...) {
      _exit(45);
    }
    _exit(46);
  }
  for (int i = 0; i < 100 && !fs::exists(pid_file); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto start = std::chrono::steady_clock::now();
  kill(child, SIGTERM);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 43);
  EXPECT_LT(seconds, 5);
  pid_t gmsh_pid = 0;
  std::ifstream(pid_file) >> gmsh_pid;
  ASSERT_GT(gmsh_pid, 0);
  EXPECT_NE(kill(gmsh_pid, 0), 0) << "gmsh's process outlived the run";
}

TEST(MeshWire, AMeshComesBackWhole) {
  const Mesh m = load_geo("cylinder.geo", {}, 2);
  const Mesh back = decode_mesh(encode_mesh(m), "f");
  EXPECT_EQ(back.order, m.order);
  EXPECT_EQ(back.x, m.x);
  EXPECT_EQ(back.tets, m.tets);
  EXPECT_EQ(back.tet_volume, m.tet_volume);
  EXPECT_EQ(back.volume_names, m.volume_names);
  EXPECT_EQ(back.surfaces, m.surfaces);
  EXPECT_EQ(back.surface_tets, m.surface_tets);
  EXPECT_EQ(back.node_groups, m.node_groups);
}

// The bytes come from a process that parsed untrusted input: cut or altered, they are refused
// or give a mesh whose every index is in range; never a crash (the sanitized build watches).
TEST(MeshWire, DamagedBytesNeverPassAsAMesh) {
  const std::string good = encode_mesh(load_geo("block.geo", {}));
  for (size_t n = 0; n < good.size(); n += 1 + n / 64) {
    SCOPED_TRACE(n);
    expect_input_error([&] { decode_mesh(std::string_view(good).substr(0, n), "f.geo"); },
                       {"f.geo: the mesh gmsh read could not be handed over"});
  }
  std::mt19937 random(7);
  int refused = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    std::string bad = good;
    for (int k = 0; k < 3; ++k) bad[random() % bad.size()] = static_cast<char>(random());
    try {
      const Mesh m = decode_mesh(bad, "f.geo");
      for (int64_t v : m.tets) ASSERT_TRUE(v >= 0 && v < m.num_nodes());
      for (const auto& [name, faces] : m.surfaces)
        for (int64_t v : faces) ASSERT_TRUE(v >= 0 && v < m.num_nodes());
    } catch (const InputError&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace hs::test
