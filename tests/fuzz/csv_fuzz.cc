/// libFuzzer target: CSV tables (io::CsvTable::Parse), then every column read as numbers and as
/// text, as `fit` and `stats --csv` read them. Any input is either read or rejected with a
/// std::exception whose message names the source; anything else is a finding.
#include <exception>
#include <sstream>
#include <string>

#include "fuzz/fuzz_files.h"
#include "io/csv.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string source = "fuzz-input.csv";
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const hoof::io::CsvTable table = hoof::io::CsvTable::Parse(in, source);
    for (const std::string& column : table.header()) {
      (void)table.Texts(column);
      try {
        (void)table.Numbers(column);
      } catch (const std::exception& e) {
        hoof::fuzz::RequireNamed(e.what(), source);
      }
    }
    (void)table.Column("no such column \x01");
  } catch (const std::exception& e) {
    hoof::fuzz::RequireNamed(e.what(), source);
  }
  return 0;
}
