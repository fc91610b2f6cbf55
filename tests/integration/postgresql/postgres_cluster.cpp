// PostgresCluster (postgres_cluster.hpp): shell commands through std::system, each prefixed with
// `runuser -u nobody --` when running as root; the cluster directory is handed to that user.
#include "postgres_cluster.hpp"

#include "support/test_support.hpp"

#include <pwd.h>
#include <unistd.h>

#include <cstdlib>
#include <stdexcept>

namespace rr::testing {

namespace fs = std::filesystem;

namespace {

std::string quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

}  // namespace

std::optional<fs::path> PostgresCluster::bin_dir() {
  std::optional<fs::path> best;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator("/usr/lib/postgresql", ec)) {
    fs::path bin = entry.path() / "bin";
    if (fs::exists(bin / "initdb") && fs::exists(bin / "pg_ctl") && fs::exists(bin / "psql") &&
        (!best || bin.string() > best->string())) {
      best = bin;
    }
  }
  return best;
}

PostgresCluster::PostgresCluster() {
  bin_ = bin_dir().value_or("");
  if (bin_.empty()) throw std::runtime_error("PostgreSQL is not installed (/usr/lib/postgresql/*/bin)");
  char pattern[] = "/tmp/rr-pg-XXXXXX";  // short: a unix socket path has at most 107 bytes
  if (!::mkdtemp(pattern)) throw std::runtime_error("cannot create a temporary directory");
  dir_ = pattern;
  if (::geteuid() == 0) {
    const passwd* nobody = ::getpwnam("nobody");
    if (!nobody || ::chown(dir_.c_str(), nobody->pw_uid, nobody->pw_gid) != 0) {
      throw std::runtime_error("cannot hand " + dir_.string() + " to the user nobody");
    }
  }
  // trust on the socket only (the directory is the cluster user's); no fsync: a test cluster.
  if (run((bin_ / "initdb").string() + " -D " + quoted((dir_ / "data").string()) +
          " -A trust -U rr -E UTF8 --no-sync") != 0) {
    throw std::runtime_error("initdb failed:\n" + log());
  }
  start();
}

PostgresCluster::~PostgresCluster() {
  if (running_) run((bin_ / "pg_ctl").string() + " -D " + quoted((dir_ / "data").string()) + " -m immediate -w stop");
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

int PostgresCluster::run(const std::string& command) const {
  const std::string as_user = ::geteuid() == 0 ? "runuser -u nobody -- " : "";
  const std::string line = "cd / && " + as_user + command + " >> " + quoted((dir_ / "commands.log").string()) + " 2>&1";
  int status = std::system(line.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string PostgresCluster::log() const {
  std::string out;
  for (const char* name : {"commands.log", "server.log"}) {
    std::error_code ec;
    if (fs::exists(dir_ / name, ec)) out += read_file(dir_ / name);
  }
  return out;
}

void PostgresCluster::start() {
  const std::string options = "-k " + dir_.string() + " -c listen_addresses='' -c fsync=off -c max_connections=60";
  if (run((bin_ / "pg_ctl").string() + " -D " + quoted((dir_ / "data").string()) + " -o " + quoted(options) + " -l " +
          quoted((dir_ / "server.log").string()) + " -w -t 30 start") != 0) {
    throw std::runtime_error("pg_ctl start failed:\n" + log());
  }
  running_ = true;
}

void PostgresCluster::stop() {
  if (run((bin_ / "pg_ctl").string() + " -D " + quoted((dir_ / "data").string()) + " -m fast -w -t 30 stop") != 0) {
    throw std::runtime_error("pg_ctl stop failed:\n" + log());
  }
  running_ = false;
}

std::string PostgresCluster::url(const std::string& database) const {
  return "postgresql://rr@/" + database + "?host=" + dir_.string();
}

void PostgresCluster::create_database(const std::string& name) { query("postgres", "CREATE DATABASE " + name); }

std::string PostgresCluster::query(const std::string& database, const std::string& sql) const {
  const fs::path out = dir_ / "query.out";
  const std::string command = (bin_ / "psql").string() + " -X -q -At -v ON_ERROR_STOP=1 -h " + dir_.string() +
                              " -U rr -d " + database + " -c " + quoted(sql) + " > " + quoted(out.string());
  const std::string as_user = ::geteuid() == 0 ? "runuser -u nobody -- sh -c " + quoted(command) : command;
  if (std::system(("cd / && " + as_user + " 2>> " + quoted((dir_ / "commands.log").string())).c_str()) != 0) {
    throw std::runtime_error("psql failed on: " + sql + "\n" + log());
  }
  std::string text = read_file(out);
  while (!text.empty() && text.back() == '\n') text.pop_back();
  return text;
}

void PostgresStoreTest::SetUp() {
  if (!PostgresCluster::bin_dir()) {
    GTEST_SKIP() << "PostgreSQL is not installed (no /usr/lib/postgresql/*/bin/initdb): apt-get install postgresql";
  }
  cluster_ = std::make_unique<PostgresCluster>();
  cluster_->create_database("rr_test");
}

rr::server::ServerConfig PostgresStoreTest::config(const std::string& tokens_name) const {
  rr::server::ServerConfig c = test_server_config();
  c.store_url = cluster_->url("rr_test");
  c.store_timeout_ms = 1000;
  c.store_pool_size = 4;
  if (!tokens_name.empty()) {
    fs::path file = output_dir("integration") / (tokens_name + ".tokens");
    write_file(file, "alice:" + alice + "\nbob:" + bob + "\n");
    c.api_token_file = file;
  }
  return c;
}

}  // namespace rr::testing
