#include "cli/commands.h"

namespace penumbra {

std::string& commandLine() {
  static std::string line;
  return line;
}

}  // namespace penumbra
