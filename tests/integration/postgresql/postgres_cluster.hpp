// A real PostgreSQL server for the shared-store tests: initdb and pg_ctl from Debian's package
// (/usr/lib/postgresql/<version>/bin) in a temporary directory, listening on a unix socket there
// only (no TCP port to collide with), run as `nobody` when the tests run as root (PostgreSQL
// refuses to run as root). Each test gets its own cluster, so tests may run in parallel.
#pragma once

#include "integration/server_fixture.hpp"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace rr::testing {

class PostgresCluster {
 public:
  // The directory of initdb/pg_ctl/psql, or nullopt when PostgreSQL is not installed.
  static std::optional<std::filesystem::path> bin_dir();

  PostgresCluster();   // initdb and start; throws std::runtime_error (with the server's log) on failure
  ~PostgresCluster();  // stops the server at once and removes the directory
  PostgresCluster(const PostgresCluster&) = delete;
  PostgresCluster& operator=(const PostgresCluster&) = delete;

  void stop();  // fast shutdown: clients are disconnected
  void start();
  // A URL for `database` (created with create_database, or "postgres").
  std::string url(const std::string& database = "postgres") const;
  void create_database(const std::string& name);
  // psql's unaligned output of `sql` (rows on lines, columns joined by '|'), trailing newline cut.
  std::string query(const std::string& database, const std::string& sql) const;

 private:
  int run(const std::string& command) const;  // as the cluster's user; output appended to the log
  std::string log() const;

  std::filesystem::path bin_;
  std::filesystem::path dir_;
  bool running_ = false;
};

// Tokens of the servers that PostgresStoreTest::config gives a token file.
inline const std::string alice = "alice-0123456789abcdef";
inline const std::string bob = "bob-fedcba9876543210XYZ";

// A cluster with an empty database rr_test per test (skipped, saying why, without PostgreSQL), and
// server configurations on it.
class PostgresStoreTest : public ::testing::Test {
 protected:
  void SetUp() override;
  // A test server's config on rr_test (store timeout 1 s, 4 connections); with tokens when named.
  rr::server::ServerConfig config(const std::string& tokens_name = "") const;
  std::string sql(const std::string& query) const { return cluster_->query("rr_test", query); }

  std::unique_ptr<PostgresCluster> cluster_;
};

}  // namespace rr::testing
