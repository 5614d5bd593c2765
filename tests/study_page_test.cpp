// SPDX-License-Identifier: Apache-2.0
// Issue 35: the study's index.html in a real headless browser (Debian
// chromium): the page renders, its chart loads, and the numbers of its run
// table are those of study.csv. Label "browser" (scripts/install-deps.sh
// installs chromium).
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/dvisim_fixture.hpp"

namespace dvi::testing {
namespace {

// study.csv's rows as fields (RFC 4180 quoting).
std::vector<std::vector<std::string>> ParseCsv(const std::string& text) {
  std::vector<std::vector<std::string>> rows(1, std::vector<std::string>(1));
  bool quoted = false;
  for (std::size_t k = 0; k < text.size(); ++k) {
    const char c = text[k];
    if (quoted) {
      if (c == '"' && k + 1 < text.size() && text[k + 1] == '"') {
        rows.back().back() += '"';
        ++k;
      } else if (c == '"') {
        quoted = false;
      } else {
        rows.back().back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      rows.back().emplace_back();
    } else if (c == '\n') {
      rows.emplace_back(1);
    } else {
      rows.back().back() += c;
    }
  }
  if (rows.back().size() == 1 && rows.back()[0].empty()) rows.pop_back();
  return rows;
}

std::string Unescape(std::string text) {
  for (const auto& [entity, character] : {std::pair<std::string, std::string>{"&lt;", "<"},
                                          {"&gt;", ">"},
                                          {"&quot;", "\""},
                                          {"&nbsp;", "\u00a0"},
                                          {"&amp;", "&"}}) {
    for (std::size_t at = text.find(entity); at != std::string::npos;
         at = text.find(entity, at + character.size()))
      text.replace(at, entity.size(), character);
  }
  return text;
}

// The cells of the rows of the table with this id, as the browser's DOM
// holds them (header row included).
std::vector<std::vector<std::string>> TableCells(const std::string& dom, const std::string& id) {
  std::vector<std::vector<std::string>> rows;
  const std::size_t begin = dom.find("<table id=\"" + id + "\"");
  const std::size_t end = dom.find("</table>", begin);
  if (begin == std::string::npos || end == std::string::npos) return rows;
  const std::string table = dom.substr(begin, end - begin);
  for (std::size_t row = table.find("<tr>"); row != std::string::npos;
       row = table.find("<tr>", row + 4)) {
    const std::size_t row_end = table.find("</tr>", row);
    rows.emplace_back();
    for (std::size_t cell = table.find("<t", row + 4); cell != std::string::npos && cell < row_end;
         cell = table.find("<t", cell + 1)) {
      const std::size_t open_end = table.find('>', cell);
      const std::size_t close = table.find("</t", open_end);
      rows.back().push_back(Unescape(table.substr(open_end + 1, close - open_end - 1)));
      cell = close;
    }
  }
  return rows;
}

class StudyPageTest : public DvisimBinaryTest {
 protected:
  // Runs chromium headless on file://page with `mode` (--dump-dom or
  // --screenshot=...); returns its standard output.
  std::string Browser(const std::string& mode, const std::string& page) {
    const std::string output = Path("browser.out");
    const std::string command = std::string("'") + DVI_CHROMIUM +
                                "' --headless --no-sandbox --disable-gpu "
                                "--disable-background-networking --no-first-run --user-data-dir='" +
                                Path("profile") + "' --window-size=1400,5000 " + mode +
                                " 'file://" + page + "' >'" + output + "' 2>/dev/null";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    return Slurp(output);
  }
};

TEST_F(StudyPageTest, RendersWithItsChartAndTheNumbersOfTheCsv) {
  ASSERT_TRUE(std::filesystem::exists(DVI_CHROMIUM))
      << "chromium not found (" << DVI_CHROMIUM << "): scripts/install-deps.sh installs it";
  const std::string out = Path("study");
  const RunOutcome study =
      Dvisim("study '" DVI_TEST_SCENES_DIR "/study/box_lcs_saturation.json' --out '" + out +
             "' --repeats 1");
  ASSERT_EQ(study.exit_code, 0) << study.err;
  const std::string page = out + "/index.html";
  const std::string dom = Browser("--dump-dom", page);
  ASSERT_NE(dom.find("<h1>Study of box-lcs-saturation</h1>"), std::string::npos)
      << dom.substr(0, 500);
  // The chart is a data: URI the browser decoded: onload marked it.
  const std::size_t image = dom.find("<img id=\"work-precision\"");
  ASSERT_NE(image, std::string::npos);
  const std::string tag = dom.substr(image, dom.find('>', image) - image);
  EXPECT_NE(tag.find("data-loaded=\"yes\""), std::string::npos) << tag.substr(tag.size() - 200);
  // No resource outside the page.
  EXPECT_EQ(dom.find("src=\"http"), std::string::npos);
  EXPECT_EQ(dom.find("<script src"), std::string::npos);

  const std::vector<std::vector<std::string>> csv = ParseCsv(Slurp(out + "/study.csv"));
  const std::vector<std::vector<std::string>> table = TableCells(dom, "runs");
  ASSERT_EQ(table.size(), csv.size());
  for (std::size_t r = 0; r < csv.size(); ++r) EXPECT_EQ(table[r], csv[r]) << "row " << r;
  ASSERT_FALSE(TableCells(dom, "slopes").empty());
  ASSERT_FALSE(TableCells(dom, "stability-rtol").empty());

  // The rendered page: a PNG of the window's size, not a blank one (a
  // white 1400×5000 page compresses to a few kB; the chart and tables do not).
  const std::string shot = Path("page.png");
  Browser("--screenshot='" + shot + "'", page);
  const std::string png = Slurp(shot);
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const auto big_endian = [&](std::size_t at) {
    return (static_cast<unsigned char>(png[at]) << 24) |
           (static_cast<unsigned char>(png[at + 1]) << 16) |
           (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
  };
  EXPECT_EQ(big_endian(16), 1400u);
  EXPECT_EQ(big_endian(20), 5000u);
  constexpr std::size_t kBlankPageBytes = 50'000;
  EXPECT_GT(png.size(), kBlankPageBytes);
}

}  // namespace
}  // namespace dvi::testing
