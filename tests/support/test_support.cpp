#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rr::testing {

std::filesystem::path source_dir() { return ROOMRENDER_SOURCE_DIR; }

std::filesystem::path examples_dir() { return source_dir() / "examples"; }

std::optional<std::filesystem::path> shared_data_dir() {
  auto dir = source_dir().parent_path() / "shared" / "data";
  if (std::filesystem::is_directory(dir)) return dir;
  // CI has the data: there a test that would skip for want of it fails instead (.ci/run sets this).
  if (std::getenv("ROOMRENDER_REQUIRE_SHARED")) throw std::runtime_error(dir.string() + " is absent");
  return std::nullopt;
}

std::filesystem::path output_dir(const std::string& suite) {
  auto dir = std::filesystem::path(ROOMRENDER_BINARY_DIR) / "test-output" / suite;
  std::filesystem::create_directories(dir);
  return dir;
}

std::filesystem::path fresh_output_dir(const std::string& suite) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  if (!test) throw std::logic_error("fresh_output_dir is for a running test");
  std::string name = std::string(test->test_suite_name()) + "." + test->name();
  std::replace(name.begin(), name.end(), '/', '_');
  const std::filesystem::path dir = output_dir(suite) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

namespace {
double cpu_ms(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}
}  // namespace

double thread_cpu_ms() { return cpu_ms(CLOCK_THREAD_CPUTIME_ID); }
double process_cpu_ms() { return cpu_ms(CLOCK_PROCESS_CPUTIME_ID); }

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

void write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

nlohmann::json example_request(const std::string& stem, int width, int height) {
  nlohmann::json r = nlohmann::json::parse(read_file(examples_dir() / (stem + ".json")));
  r["options"]["width"] = width;
  r["options"]["height"] = height;
  return r;
}

nlohmann::json unit_cube_mesh() {
  return {{"vertices",
           {{-0.5, -0.5, -0.5},
            {0.5, -0.5, -0.5},
            {-0.5, 0.5, -0.5},
            {0.5, 0.5, -0.5},
            {-0.5, -0.5, 0.5},
            {0.5, -0.5, 0.5},
            {-0.5, 0.5, 0.5},
            {0.5, 0.5, 0.5}}},
          {"faces", {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}}}};
}

std::vector<std::filesystem::path> example_files() {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(examples_dir())) {
    if (entry.path().extension() == ".json") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string ids_as_ascii(const IdBuffer& ids) {
  std::string art;
  for (int y = 0; y < ids.height; ++y) {
    for (int x = 0; x < ids.width; ++x) {
      uint32_t id = ids.at(x, y);
      art += id == background_id ? '.' : char('0' + id % 10);
    }
    art += '\n';
  }
  return art;
}

IdDiff compare_ids(const IdBuffer& truth, const IdBuffer& test, bool edges_of_both) {
  EXPECT_EQ(truth.width, test.width);
  EXPECT_EQ(truth.height, test.height);
  IdDiff d;
  for (int y = 0; y < truth.height; ++y) {
    for (int x = 0; x < truth.width; ++x) {
      if (truth.at(x, y) == test.at(x, y)) continue;
      bool edge = is_edge_pixel(truth, x, y) || (edges_of_both && is_edge_pixel(test, x, y));
      ++(edge ? d.edge : d.interior);
    }
  }
  return d;
}

RunResult run_roomrender(const std::string& args, const std::filesystem::path& dir, const std::string& stdin_file) {
  const std::string command = "cd '" + dir.string() + "' && '" ROOMRENDER_BINARY_DIR "/roomrender' " + args +
                              (stdin_file.empty() ? "" : " <'" + stdin_file + "'") + " >stdout.bin 2>stderr.txt";
  const int status = std::system(command.c_str());
  RunResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = read_file(dir / "stdout.bin");
  result.err = read_file(dir / "stderr.txt");
  return result;
}

}  // namespace rr::testing
