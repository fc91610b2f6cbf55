// A user's homes kept in PostgreSQL: thirty furnished Sweet Home 3D homes (the nine and copies moved
// apart) stored over HTTP at the default budgets all answer 201, draw, and draw the same bytes on a
// server started afterwards on the same database (integration/stored_homes.hpp).
#include "integration/stored_homes.hpp"
#include "postgres_cluster.hpp"
#include "support/sweet_homes.hpp"

namespace {

using namespace rr::testing;

TEST_F(PostgresStoreTest, ThirtyFurnishedHomesAreKeptAcrossARestart) {
  if (sweet_home_files().empty()) GTEST_SKIP() << "../shared/data is absent";
  rr::server::ServerConfig server = config();
  server.render_timeout_ms = 60'000;  // a rebuild of a 218k-polygon home on a loaded machine
  expect_homes_kept_across_restart(server, 30);
}

}  // namespace
