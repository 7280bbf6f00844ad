// IntegerDecompressor is header-only (its hot path must inline into the item decoders);
// this unit checks that the header stands on its own.
#include "laz/integer_decompressor.hpp"
