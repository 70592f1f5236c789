#pragma once
/// @file The error of the UPER codec and of the message codecs built on it.
///
/// A decode error names what was wrong (which field, which value) and where (the bit offset in
/// the input), so that a bad packet in a capture can be found and explained.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace tb::its::asn1 {

enum class Error : std::uint8_t {
  kTruncated,           ///< input ended inside a field
  kValueOutOfRange,     ///< an integer outside its constraint (decoded or to be encoded)
  kSizeOutOfRange,      ///< a SEQUENCE OF / string length outside its SIZE constraint
  kUnknownExtension,    ///< an extension value, alternative or enumeration we cannot hold
  kUnsupported,         ///< valid ASN.1 that this codec does not implement (named in field)
  kWrongMessageId,      ///< ItsPduHeader.messageID is not the one the decoder expects
  kUnsupportedVersion,  ///< ItsPduHeader.protocolVersion not handled
  kBufferTooSmall,      ///< encode: output buffer full
  kTrailingData,        ///< decode: non-zero bits or whole octets after the message
};

std::string_view to_string(Error e);

/// What went wrong, in which field, with which value, at which bit of the input (or output).
struct CodecError {
  Error code = Error::kTruncated;
  const char* field = "";  ///< static string: the ASN.1 component name, e.g. "headingValue"
  std::int64_t value = 0;  ///< the offending value where there is one
  std::size_t bit_offset = 0;
};

/// "value out of range: headingValue = 3700 (bit 123)".
std::string to_string(const CodecError& e);

}  // namespace tb::its::asn1
