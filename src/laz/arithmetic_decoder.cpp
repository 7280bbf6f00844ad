// Cold paths of the arithmetic decoder (error reporting), kept out of the inline hot paths.
#include "laz/arithmetic_decoder.hpp"

#include <string>

#include "core/error.hpp"

namespace lidarscout::laz {

void ArithmeticDecoder::fail_corrupt(std::uint32_t bits) {
    throw Error("corrupt arithmetic-coded data: a raw " + std::to_string(bits) +
                "-bit field decoded to a value that does not fit");
}

}  // namespace lidarscout::laz
