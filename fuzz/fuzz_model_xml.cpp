// libFuzzer entry point for check_model_xml (input_checks.hpp): any bytes must be
// accepted or refused with a clear InputError; nothing else may happen.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz/input_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  (void)sodaevo::fuzz::check_model_xml(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
