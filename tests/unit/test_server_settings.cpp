// The settings table (server/settings.hpp) against docs/api.md and against itself: the docs' settings
// table has one row per setting, in the table's order, each with the setting's variable, default and
// unit, and no other row; every setting whose default is a number or a switch takes that default back
// through its flag and through its variable, and names the variable when its value is wrong.
#include "server/serve_command.hpp"
#include "server/settings.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace rr::server {
namespace {

// One row of docs/api.md's settings table, its cells trimmed.
struct DocsRow {
  size_t line = 0;
  std::string flag;      // "--port" (the backticks dropped)
  std::string variable;  // "`ROOMRENDER_PORT`"
  std::string default_cell;
  std::string unit;
};

std::string trim(const std::string& text) {
  size_t begin = text.find_first_not_of(' ');
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(' ') - begin + 1);
}

std::string without_backticks(std::string text) {
  text.erase(std::remove(text.begin(), text.end(), '`'), text.end());
  return text;
}

// The rows under the header "| flag | variable | default | unit | meaning |", up to the first line that
// is not a table row.
std::vector<DocsRow> docs_settings_rows() {
  std::ifstream in(std::string(ROOMRENDER_SOURCE_DIR) + "/docs/api.md");
  EXPECT_TRUE(in) << "cannot open docs/api.md";
  std::vector<DocsRow> rows;
  std::string line;
  size_t number = 0;
  bool in_table = false;
  while (std::getline(in, line)) {
    ++number;
    if (line == "| flag | variable | default | unit | meaning |") {
      in_table = true;
      std::getline(in, line);  // |---|---|...
      ++number;
      continue;
    }
    if (!in_table) continue;
    if (!line.starts_with("|")) break;
    std::vector<std::string> cells;
    std::stringstream cut(line.substr(1));
    for (std::string cell; std::getline(cut, cell, '|');) cells.push_back(trim(cell));
    EXPECT_GE(cells.size(), 5u) << "docs/api.md:" << number << " has fewer than 5 cells: " << line;
    cells.resize(5);
    rows.push_back({number, without_backticks(cells[0]), cells[1], cells[2], cells[3]});
  }
  EXPECT_TRUE(in_table) << "docs/api.md has no line '| flag | variable | default | unit | meaning |'";
  return rows;
}

TEST(ServerSettings, DocsApiTableHasEveryRowWithItsVariableDefaultAndUnit) {
  const std::vector<DocsRow> docs = docs_settings_rows();
  std::map<std::string, const DocsRow*> docs_by_flag;
  for (const DocsRow& row : docs) {
    if (!docs_by_flag.emplace(row.flag, &row).second) {
      ADD_FAILURE() << "docs/api.md:" << row.line << " lists " << row.flag << " a second time";
    }
    if (!find_setting(row.flag)) {
      ADD_FAILURE() << "docs/api.md:" << row.line << " lists " << row.flag
                    << ", which is not a server setting (server/settings.cpp)";
    }
  }
  std::vector<std::string> code_order, docs_order;
  for (const ServerSetting& setting : server_settings()) {
    const std::string flag(setting.flag);
    auto found = docs_by_flag.find(flag);
    if (found == docs_by_flag.end()) {
      ADD_FAILURE() << "server setting " << flag << " (" << setting.env() << ", default " << setting.default_text()
                    << ") has no row in docs/api.md's settings table";
      continue;
    }
    code_order.push_back(flag);
    const DocsRow& row = *found->second;
    EXPECT_EQ(row.variable, std::string("`").append(setting.env()).append("`"))
        << "docs/api.md:" << row.line << " " << flag;
    // The default cell starts with the default (backticks aside) and may go on with an explanation.
    const std::string shown = without_backticks(row.default_cell);
    const std::string expected = setting.default_text();
    EXPECT_TRUE(shown.starts_with(expected) && (shown.size() == expected.size() || shown[expected.size()] == ' '))
        << "docs/api.md:" << row.line << " gives " << flag << " the default '" << row.default_cell
        << "'; the code's default is " << expected;
    EXPECT_EQ(row.unit, setting.unit) << "docs/api.md:" << row.line << " " << flag;
  }
  for (const DocsRow& row : docs) {
    if (find_setting(row.flag)) docs_order.push_back(row.flag);
  }
  EXPECT_EQ(docs_order, code_order) << "docs/api.md lists the settings in another order than server/settings.cpp";
}

// A value outside its range (or no number at all) for every numeric setting.
std::string wrong_value(const nlohmann::ordered_json& value) { return value.is_boolean() ? "2" : "many"; }

TEST(ServerSettings, NumericDefaultsGoBackThroughFlagAndVariable) {
  auto no_variables = [](const char*) -> std::optional<std::string> { return std::nullopt; };
  const std::string defaults = config_json(serve_config_from({}, no_variables));
  size_t checked = 0;
  for (const ServerSetting& setting : server_settings()) {
    const nlohmann::ordered_json value = setting.member.report(ServerConfig{});
    if (!value.is_number() && !value.is_boolean()) continue;
    ++checked;
    const std::string flag(setting.flag), variable = setting.env(), text = setting.default_text();
    std::vector<std::string> args = {flag, text};
    EXPECT_EQ(config_json(serve_config_from(args, no_variables)), defaults) << flag << " " << text;
    auto from_variable = [&](const char* name) -> std::optional<std::string> {
      return name == variable ? std::optional<std::string>(text) : std::nullopt;
    };
    EXPECT_EQ(config_json(serve_config_from({}, from_variable)), defaults) << variable << "=" << text;
    auto wrong_variable = [&](const char* name) -> std::optional<std::string> {
      return name == variable ? std::optional<std::string>(wrong_value(value)) : std::nullopt;
    };
    try {
      serve_config_from({}, wrong_variable);
      ADD_FAILURE() << variable << "=" << wrong_value(value) << " was accepted";
    } catch (const UsageError& e) {
      EXPECT_TRUE(std::string(e.what()).starts_with(variable + " must be")) << e.what();
    }
  }
  EXPECT_GT(checked, 40u);
}

TEST(ServerSettings, ImageSideStopsAtTheRasterizersBound) {
  // Exact 64-bit edge functions on a 2^-14 pixel grid need sides of at most 65536 pixels
  // (docs/architecture.md, "Precision of the rasterizer").
  auto no_variables = [](const char*) -> std::optional<std::string> { return std::nullopt; };
  const std::vector<std::string> largest = {"--max-image-side", "65536"}, over = {"--max-image-side", "65537"};
  EXPECT_EQ(serve_config_from(largest, no_variables).limits.max_image_side, 65536);
  try {
    serve_config_from(over, no_variables);
    ADD_FAILURE() << "--max-image-side 65537 was accepted";
  } catch (const UsageError& e) {
    EXPECT_TRUE(std::string(e.what()).starts_with("--max-image-side must be an integer in [1, 65536]")) << e.what();
  }
}

}  // namespace
}  // namespace rr::server
