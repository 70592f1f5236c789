// libFuzzer target: the Ieee1609Dot2Data and certificate decoders on arbitrary bytes. Whatever
// decodes must re-encode, the re-encoding must decode to the same value and encode to the same
// octets, and the tbsData (toBeSigned certificate) octets kept for the signature must be the
// encoding of the tbsData (ToBeSignedCertificate) when nothing unknown was skipped.

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <span>

#include "its-station/security/ieee1609dot2.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace tb::its::security;
  const std::span<const std::uint8_t> in(data, size);
  if (auto d = decode_data(in)) {
    const Bytes bytes = encode(*d);
    auto again = decode_data(bytes);
    if (!again || !(*again == *d))
      std::abort();
    if (encode(*again) != bytes)
      std::abort();
    if (again->content == Ieee1609Dot2Data::Content::kSignedData &&
        again->signed_data.tbs_encoding != encode(again->signed_data.tbs))
      std::abort();
  }
  if (auto c = decode_certificate(in)) {
    // A decoded certificate is written as it came; its toBeSigned octets lie inside those.
    const Bytes bytes = encode(*c);
    if (bytes != c->encoding || c->tbs_octets().empty())
      std::abort();
    auto again = decode_certificate(bytes);
    if (!again || !(*again == *c) || again->encoding != bytes)
      std::abort();
    // Re-encoded from its fields, toBeSigned is the octets kept for the issuer's signature
    // (when nothing unknown was skipped, the received octets are those too).
    Certificate fields = *again;
    fields.encoding.clear();
    fields.tbs_offset = fields.tbs_length = 0;
    auto rebuilt = decode_certificate(encode(fields));
    if (!rebuilt || !std::ranges::equal(rebuilt->tbs_octets(), encode(rebuilt->tbs)))
      std::abort();
  }
  return 0;
}
