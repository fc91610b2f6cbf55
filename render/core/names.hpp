// The name table every named choice goes through: rows of {value, name} (a row type may carry more,
// e.g. a summary or a function), looked up by name or by value, iterated in row order. The row
// order is the order the schema and the error messages list the names in. Tables are constexpr
// data over static arrays; a lookup is a linear scan (every table has a handful of rows).
#pragma once

#include <array>
#include <cassert>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>

namespace rr {

template <class Value>
struct NameRow {
  Value value;
  const char* name;
};

// Row needs a `name` member (const char*); lookups by value also need a `value` member.
template <class Row>
class NameTable {
 public:
  constexpr NameTable(std::span<const Row> rows) : rows_(rows) {}
  template <size_t N>
  constexpr NameTable(const std::array<Row, N>& rows) : rows_(rows) {}

  const Row* find(std::string_view name) const {
    for (const Row& row : rows_) {
      if (name == row.name) return &row;
    }
    return nullptr;
  }

  // Every value of the enum has a row: the schema-vs-tables test checks the names, and a missing
  // row is a programming error, not bad input.
  template <class Value>
  const Row& row(Value value) const {
    for (const Row& row : rows_) {
      if (row.value == value) return row;
    }
    assert(false && "every value has a row in its name table");
    return rows_.front();
  }
  template <class Value>
  const char* name(Value value) const {
    return row(value).name;
  }

  // "a, b, c": the list an error message offers ("must be one of: a, b, c").
  std::string choices() const {
    std::string out;
    for (const Row& row : rows_) out += (out.empty() ? "" : ", ") + std::string(row.name);
    return out;
  }

  constexpr size_t size() const { return rows_.size(); }
  constexpr const Row& operator[](size_t i) const { return rows_[i]; }
  constexpr auto begin() const { return rows_.begin(); }
  constexpr auto end() const { return rows_.end(); }

 private:
  std::span<const Row> rows_;
};

}  // namespace rr
