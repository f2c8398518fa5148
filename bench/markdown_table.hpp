// The Markdown tables of the benchmarks' documents (identity-bench, jointflow-bench): a header, its
// alignment row and one line per row, every cell between "| " and " |". Written in one place so
// that the document writers say what goes in a table, not how its pipes are laid out. Header-only,
// as text_format.hpp.
#pragma once

#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace jointflow::bench {

class MarkdownTable {
 public:
  struct Column {
    std::string name;
    bool right = false;  ///< right-aligned ("---:"), as counts and scores are in identity.md
  };

  explicit MarkdownTable(std::vector<Column> columns) : columns_(std::move(columns)) {}

  /// Columns that all align left ("---"), as in benchmarks.md.
  static MarkdownTable leftAligned(const std::vector<std::string>& names) {
    std::vector<Column> columns;
    for (const std::string& name : names) columns.push_back({name});
    return MarkdownTable(columns);
  }

  MarkdownTable& row(const std::vector<std::string>& cells) {
    rows_.push_back(cells);
    return *this;
  }

  bool empty() const { return rows_.empty(); }

  std::string str() const {
    std::ostringstream s;
    s << "|";
    for (const Column& c : columns_) s << " " << c.name << " |";
    s << "\n|";
    for (const Column& c : columns_) s << (c.right ? "---:|" : "---|");
    s << "\n";
    for (const auto& cells : rows_) {
      s << "|";
      for (const std::string& cell : cells) s << " " << cell << " |";
      s << "\n";
    }
    return s.str();
  }

 private:
  std::vector<Column> columns_;
  std::vector<std::vector<std::string>> rows_;
};

}  // namespace jointflow::bench
