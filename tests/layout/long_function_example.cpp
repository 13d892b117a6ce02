// Deliberately long: the test function_length_catches_long checks this
// file with the sources and passes only if the check reports too_long, at
// 101 lines, and nothing else. Braces in comments {, in strings, in
// character literals and in raw strings do not count, nor does a digit
// separator open a character literal.
#include <string>

namespace lem {
namespace {

const char* const kBraces[] = {"{", "}", "{{"};

int short_one(int x) {
  const std::string s = "}}} {";
  return x + static_cast<int>(s.size()) + '}';
}

struct Holder {
  int inline_member(int x) const { return x + '{'; }
};

}  // namespace

int too_long(int x) {
  int y = 1'000;
  const char* raw = R"(}{{)";
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  y += x;
  return y + raw[0];
}

}  // namespace lem
