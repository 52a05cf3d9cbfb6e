#include "app/deprecated_option.h"

#include <cstdio>

namespace lb::app {

CLI::Option* add_deprecated_alias(CLI::App& cmd, CLI::Option* current, const std::string& old_name,
                                  std::string& target) {
  const std::string new_name = current->get_name();
  return cmd
      .add_option_function<std::string>(
          old_name,
          [&target, current, old_name, new_name](const std::string& value) {
            if (current->count() > 0)
              throw CLI::ValidationError(old_name, "the old spelling of " + new_name +
                                                       ", which is also given; keep " + new_name);
            std::fprintf(stderr, "lightbake: note: %s is deprecated, use %s\n", old_name.c_str(),
                         new_name.c_str());
            target = value;
          },
          "Deprecated spelling of " + new_name)
      ->group("");  // hidden from --help
}

}  // namespace lb::app
