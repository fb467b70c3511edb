// SPDX-License-Identifier: MIT
#include <cstdio>

double first_translation_unit();
double second_translation_unit();

int main() {
  const double a = first_translation_unit(), b = second_translation_unit();
  if (a != 0.75 || b != 0.75) {
    std::fprintf(stderr, "two-TU program computed %g and %g, expected 0.75 and 0.75\n", a, b);
    return 1;
  }
  std::printf("single_include compiles and links in two translation units\n");
  return 0;
}
