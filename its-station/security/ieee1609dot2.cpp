#include "its-station/security/ieee1609dot2.hpp"

#include "its-station/asn1/coer.hpp"

namespace tb::its::security {

using asn1::CoerReader;
using asn1::CoerWriter;
using asn1::Error;

std::uint64_t ValidityPeriod::end_seconds() const {
  const std::uint64_t d = duration;
  std::uint64_t seconds = 0;
  switch (unit) {
    case DurationUnit::kMicroseconds:
      seconds = d / 1000000;
      break;
    case DurationUnit::kMilliseconds:
      seconds = d / 1000;
      break;
    case DurationUnit::kSeconds:
      seconds = d;
      break;
    case DurationUnit::kMinutes:
      seconds = d * 60;
      break;
    case DurationUnit::kHours:
      seconds = d * 3600;
      break;
    case DurationUnit::kSixtyHours:
      seconds = d * 216000;
      break;
    case DurationUnit::kYears:
      seconds = d * 31556952;  // 1609.2 6.4.15: 365.2425 days
      break;
  }
  return std::uint64_t{start} + seconds;
}

namespace {

// ---------------------------------------------------------------------------------------------
// Writing

void put_point(CoerWriter& w, const EccP256CurvePoint& p) {
  w.choice_tag(static_cast<unsigned>(p.form));
  switch (p.form) {
    case EccP256CurvePoint::Form::kFill:
      break;
    case EccP256CurvePoint::Form::kUncompressed:
      w.octets(p.x);
      w.octets(p.y);
      break;
    default:
      w.octets(p.x);
      break;
  }
}

void put_hashed_id3s(CoerWriter& w, const std::vector<HashedId3>& ids) {
  w.quantity(ids.size());
  for (const auto& id : ids)
    w.octets(id);
}

void put_psid_ssp(CoerWriter& w, const PsidSsp& p) {
  w.preamble(false, false, p.ssp ? 1 : 0, 1);
  w.unsigned_integer(p.psid);
  if (!p.ssp)
    return;
  w.choice_tag(static_cast<unsigned>(p.ssp->kind));
  if (p.ssp->kind == Ssp::Kind::kOpaque) {
    w.var_octets(p.ssp->bytes);
  } else {
    Bytes inner;  // bitmapSsp is an extension alternative: an open type
    CoerWriter iw(inner);
    iw.var_octets(p.ssp->bytes);
    w.open_type(inner);
  }
}

void put_group_permissions(CoerWriter& w, const PsidGroupPermissions& g) {
  // DEFAULT components are absent when they hold their default (X.696 16.3, canonical).
  const bool min = g.min_chain_length != 1;
  const bool range = g.chain_length_range != 0;
  const bool ee = g.ee_type != 0x80;
  w.preamble(false, false, (min ? 4u : 0u) | (range ? 2u : 0u) | (ee ? 1u : 0u), 3);
  if (g.all_psids) {
    w.choice_tag(1);
  } else {
    w.choice_tag(0);
    w.quantity(g.psids.size());
    for (const auto& p : g.psids) {
      w.preamble(false, false, p.range ? 1 : 0, 1);
      w.unsigned_integer(p.psid);
      if (!p.range)
        continue;
      w.choice_tag(static_cast<unsigned>(p.range->kind));
      switch (p.range->kind) {
        case SspRange::Kind::kOpaque:
          w.quantity(p.range->opaque.size());
          for (const auto& o : p.range->opaque)
            w.var_octets(o);
          break;
        case SspRange::Kind::kAll:
          break;
        case SspRange::Kind::kBitmap: {
          Bytes inner;
          CoerWriter iw(inner);
          iw.var_octets(p.range->value);
          iw.var_octets(p.range->mask);
          w.open_type(inner);
          break;
        }
      }
    }
  }
  if (min)
    w.signed_integer(g.min_chain_length);
  if (range)
    w.signed_integer(g.chain_length_range);
  if (ee)
    w.u8(g.ee_type);
}

void put_tbs_certificate(CoerWriter& w, const ToBeSignedCertificate& t) {
  std::uint32_t flags = 0;
  flags |= t.region ? 0x40u : 0u;
  flags |= t.assurance_level ? 0x20u : 0u;
  flags |= t.app_permissions ? 0x10u : 0u;
  flags |= t.cert_issue_permissions ? 0x08u : 0u;
  flags |= t.cert_request_permissions ? 0x04u : 0u;
  flags |= t.can_request_rollover ? 0x02u : 0u;
  flags |= t.encryption_key ? 0x01u : 0u;
  w.preamble(true, false, flags, 7);
  w.choice_tag(static_cast<unsigned>(t.id.kind));
  switch (t.id.kind) {
    case CertificateId::Kind::kLinkageData:
      w.octets(t.id.value);
      break;
    case CertificateId::Kind::kName:
    case CertificateId::Kind::kBinaryId:
      w.var_octets(t.id.value);
      break;
    case CertificateId::Kind::kNone:
      break;
  }
  w.octets(t.craca_id);
  w.u16(t.crl_series);
  w.u32(t.validity.start);
  w.choice_tag(static_cast<unsigned>(t.validity.unit));
  w.u16(t.validity.duration);
  if (t.region)
    w.octets(*t.region);
  if (t.assurance_level)
    w.u8(*t.assurance_level);
  if (t.app_permissions) {
    w.quantity(t.app_permissions->size());
    for (const auto& p : *t.app_permissions)
      put_psid_ssp(w, p);
  }
  for (const auto* perms : {&t.cert_issue_permissions, &t.cert_request_permissions}) {
    if (!*perms)
      continue;
    w.quantity((*perms)->size());
    for (const auto& g : **perms)
      put_group_permissions(w, g);
  }
  if (t.encryption_key)
    w.octets(*t.encryption_key);
  w.choice_tag(0);  // verifyKeyIndicator verificationKey
  w.choice_tag(static_cast<unsigned>(t.verify_key.curve));
  put_point(w, t.verify_key.point);
}

void put_certificate(CoerWriter& w, const Certificate& c) {
  // A decoded certificate goes on as it came (a P2PCD answer, our own AT from its file): its
  // issuer's signature is over those octets, extension additions the decoder skips included.
  if (!c.tbs_octets().empty()) {
    w.octets(c.encoding);
    return;
  }
  w.preamble(false, false, c.signature ? 1 : 0, 1);
  w.u8(3);          // version
  w.enumerated(0);  // type explicit
  switch (c.issuer.kind) {
    case IssuerIdentifier::Kind::kSha256AndDigest:
      w.choice_tag(0);
      w.octets(c.issuer.digest);
      break;
    case IssuerIdentifier::Kind::kSelf:
      w.choice_tag(1);
      w.enumerated(static_cast<unsigned>(c.issuer.self_hash));
      break;
    case IssuerIdentifier::Kind::kSha384AndDigest:
      w.choice_tag(2);
      w.open_type(c.issuer.digest);
      break;
  }
  put_tbs_certificate(w, c.tbs);
  if (c.signature)
    coer::put(w, *c.signature);
}

void put_header(CoerWriter& w, const HeaderInfo& h) {
  const bool ext = h.inline_p2pcd_request || h.requested_certificate;
  std::uint32_t flags = 0;
  flags |= h.generation_time ? 0x20u : 0u;
  flags |= h.expiry_time ? 0x10u : 0u;
  flags |= h.generation_location ? 0x08u : 0u;
  flags |= h.p2pcd_learning_request ? 0x04u : 0u;
  flags |= h.missing_crl_identifier ? 0x02u : 0u;
  w.preamble(true, ext, flags, 6);
  w.unsigned_integer(h.psid);
  if (h.generation_time)
    w.u64(*h.generation_time);
  if (h.expiry_time)
    w.u64(*h.expiry_time);
  if (h.generation_location) {
    w.i32(h.generation_location->latitude);
    w.i32(h.generation_location->longitude);
    w.u16(h.generation_location->elevation);
  }
  if (h.p2pcd_learning_request)
    w.octets(*h.p2pcd_learning_request);
  if (h.missing_crl_identifier) {
    w.preamble(true, false, 0, 0);
    w.octets(h.missing_crl_identifier->craca_id);
    w.u16(h.missing_crl_identifier->crl_series);
  }
  if (!ext)
    return;
  w.extension_bitmap((h.inline_p2pcd_request ? 2u : 0u) | (h.requested_certificate ? 1u : 0u), 2);
  if (h.inline_p2pcd_request) {
    Bytes inner;
    CoerWriter iw(inner);
    put_hashed_id3s(iw, *h.inline_p2pcd_request);
    w.open_type(inner);
  }
  if (h.requested_certificate) {
    Bytes inner;
    CoerWriter iw(inner);
    put_certificate(iw, *h.requested_certificate);
    w.open_type(inner);
  }
}

void put_tbs_data(CoerWriter& w, const ToBeSignedData& t) {
  const auto& p = t.payload;
  w.preamble(true, false, (p.data ? 2u : 0u) | (p.ext_data_hash ? 1u : 0u), 2);
  if (p.data) {
    w.u8(kIeee1609Dot2ProtocolVersion);
    w.choice_tag(0);  // unsecuredData
    w.var_octets(*p.data);
  }
  if (p.ext_data_hash) {
    w.choice_tag(0);  // sha256HashedData
    w.octets(*p.ext_data_hash);
  }
  put_header(w, t.header);
}

void put_data(CoerWriter& w, const Ieee1609Dot2Data& d) {
  w.u8(kIeee1609Dot2ProtocolVersion);
  w.choice_tag(static_cast<unsigned>(d.content));
  if (d.content == Ieee1609Dot2Data::Content::kUnsecuredData) {
    w.var_octets(d.unsecured_data);
    return;
  }
  const auto& s = d.signed_data;
  w.enumerated(static_cast<unsigned>(s.hash_id));
  put_tbs_data(w, s.tbs);
  w.choice_tag(static_cast<unsigned>(s.signer.kind));
  switch (s.signer.kind) {
    case SignerIdentifier::Kind::kDigest:
      w.octets(s.signer.digest);
      break;
    case SignerIdentifier::Kind::kCertificate:
      w.quantity(s.signer.certificates.size());
      for (const auto& c : s.signer.certificates)
        put_certificate(w, c);
      break;
    case SignerIdentifier::Kind::kSelf:
      break;
  }
  coer::put(w, s.signature);
}

// ---------------------------------------------------------------------------------------------
// Reading. Each reader leaves the cursor failed on error; callers check ok() once at the end.

/// Reads an extension alternative's open type and fails: a valid value this codec does not
/// implement (e.g. a P-384 signature), named by @p field.
void unsupported_alternative(CoerReader& r, unsigned index, const char* field) {
  r.open_type(field);
  r.fail(Error::kUnsupported, field, index);
}

void get_point(CoerReader& r, EccP256CurvePoint& p, const char* field) {
  const unsigned tag = r.choice_tag(field);
  if (!r.ok())
    return;
  if (tag > 4) {
    r.fail(Error::kValueOutOfRange, field, tag);
    return;
  }
  p.form = static_cast<EccP256CurvePoint::Form>(tag);
  switch (p.form) {
    case EccP256CurvePoint::Form::kFill:
      break;
    case EccP256CurvePoint::Form::kUncompressed:
      r.fixed(p.x, field);
      r.fixed(p.y, field);
      break;
    default:
      r.fixed(p.x, field);
      break;
  }
}

void get_signature(CoerReader& r, Signature& s) {
  const unsigned tag = r.choice_tag("Signature");
  if (!r.ok())
    return;
  if (tag > 1) {
    unsupported_alternative(r, tag, "Signature");
    return;
  }
  s.curve = static_cast<EccCurve>(tag);
  get_point(r, s.r, "rSig");
  r.fixed(s.s, "sSig");
}

void get_hashed_id3s(CoerReader& r, std::vector<HashedId3>& ids, const char* field) {
  const std::size_t n = r.quantity(field);
  ids.resize(0);
  for (std::size_t i = 0; i < n && r.ok(); ++i)
    r.fixed(ids.emplace_back(), field);
}

/// Decodes an open type's contents with @p get, insisting that they fill it exactly.
template <typename Get>
void in_open_type(CoerReader& r, const char* field, Get get) {
  auto inner = r.open_type(field);
  if (!r.ok())
    return;
  CoerReader ir(inner);
  get(ir);
  ir.expect_end(field);
  if (!ir.ok()) {
    auto e = ir.error();
    r.fail(e.code, e.field, e.value);
  }
}

void get_psid_ssp(CoerReader& r, PsidSsp& p) {
  const bool has_ssp = r.preamble(false, nullptr, 1, "PsidSsp") != 0;
  p.psid = r.unsigned_integer("psid");
  if (!has_ssp || !r.ok())
    return;
  const unsigned tag = r.choice_tag("ssp");
  auto& ssp = p.ssp.emplace();
  if (tag == 0) {
    ssp.kind = Ssp::Kind::kOpaque;
    auto b = r.var_octets("ssp.opaque");
    ssp.bytes.assign(b.begin(), b.end());
  } else if (tag == 1) {
    ssp.kind = Ssp::Kind::kBitmap;
    in_open_type(r, "bitmapSsp", [&](CoerReader& ir) {
      auto b = ir.var_octets("bitmapSsp");
      if (b.size() > 31)
        ir.fail(Error::kSizeOutOfRange, "bitmapSsp", static_cast<std::int64_t>(b.size()));
      ssp.bytes.assign(b.begin(), b.end());
    });
  } else if (r.ok()) {
    unsupported_alternative(r, tag, "ServiceSpecificPermissions");
  }
}

void get_group_permissions(CoerReader& r, PsidGroupPermissions& g) {
  const std::uint32_t flags = r.preamble(false, nullptr, 3, "PsidGroupPermissions");
  const unsigned tag = r.choice_tag("subjectPermissions");
  if (!r.ok())
    return;
  if (tag == 1) {
    g.all_psids = true;
  } else if (tag == 0) {
    const std::size_t n = r.quantity("subjectPermissions.explicit");
    for (std::size_t i = 0; i < n && r.ok(); ++i) {
      auto& p = g.psids.emplace_back();
      const bool has_range = r.preamble(false, nullptr, 1, "PsidSspRange") != 0;
      p.psid = r.unsigned_integer("psid");
      if (!has_range || !r.ok())
        continue;
      auto& range = p.range.emplace();
      const unsigned rt = r.choice_tag("sspRange");
      if (!r.ok())
        return;
      if (rt == 0) {
        range.kind = SspRange::Kind::kOpaque;
        const std::size_t m = r.quantity("sspRange.opaque");
        for (std::size_t k = 0; k < m && r.ok(); ++k) {
          auto b = r.var_octets("sspRange.opaque");
          range.opaque.emplace_back(b.begin(), b.end());
        }
      } else if (rt == 1) {
        range.kind = SspRange::Kind::kAll;
      } else if (rt == 2) {
        range.kind = SspRange::Kind::kBitmap;
        in_open_type(r, "bitmapSspRange", [&](CoerReader& ir) {
          auto v = ir.var_octets("sspValue");
          auto m = ir.var_octets("sspBitmask");
          if (ir.ok() && (v.empty() || v.size() > 32 || m.empty() || m.size() > 32))
            ir.fail(Error::kSizeOutOfRange, "bitmapSspRange", static_cast<std::int64_t>(v.size()));
          range.value.assign(v.begin(), v.end());
          range.mask.assign(m.begin(), m.end());
        });
      } else {
        unsupported_alternative(r, rt, "SspRange");
      }
    }
  } else {
    unsupported_alternative(r, tag, "SubjectPermissions");
  }
  if ((flags & 4u) != 0) {
    g.min_chain_length = r.signed_integer("minChainLength");
    if (r.ok() && g.min_chain_length == 1)
      r.fail(Error::kValueOutOfRange, "minChainLength (default encoded)", 1);
  }
  if ((flags & 2u) != 0) {
    g.chain_length_range = r.signed_integer("chainLengthRange");
    if (r.ok() && g.chain_length_range == 0)
      r.fail(Error::kValueOutOfRange, "chainLengthRange (default encoded)", 0);
  }
  if ((flags & 1u) != 0) {
    g.ee_type = r.u8("eeType");
    if (r.ok() && g.ee_type == 0x80)
      r.fail(Error::kValueOutOfRange, "eeType (default encoded)", 0x80);
  }
}

void get_identified_region(CoerReader& r) {
  const unsigned tag = r.choice_tag("IdentifiedRegion");
  if (!r.ok())
    return;
  switch (tag) {
    case 0:  // countryOnly
      r.u16("countryOnly");
      break;
    case 1: {  // countryAndRegions
      r.u16("countryAndRegions.countryOnly");
      const std::size_t n = r.quantity("regions");
      r.octets(n, "regions");
      break;
    }
    case 2: {  // countryAndSubregions
      r.u16("countryAndSubregions.country");
      const std::size_t n = r.quantity("regionAndSubregions");
      for (std::size_t i = 0; i < n && r.ok(); ++i) {
        r.u8("region");
        const std::size_t m = r.quantity("subregions");
        r.octets(2 * m, "subregions");
      }
      break;
    }
    default:
      r.open_type("IdentifiedRegion");  // an extension alternative: kept as octets
      break;
  }
}

void get_region(CoerReader& r) {
  const unsigned tag = r.choice_tag("GeographicRegion");
  if (!r.ok())
    return;
  switch (tag) {
    case 0:  // circularRegion: center TwoDLocation, radius Uint16
      r.octets(10, "circularRegion");
      break;
    case 1: {  // rectangularRegion: SEQUENCE OF { northWest, southEast }
      const std::size_t n = r.quantity("rectangularRegion");
      r.octets(16 * n, "rectangularRegion");
      break;
    }
    case 2: {  // polygonalRegion: SEQUENCE SIZE(3..MAX) OF TwoDLocation
      const std::size_t n = r.quantity("polygonalRegion");
      if (r.ok() && n < 3)
        r.fail(Error::kSizeOutOfRange, "polygonalRegion", static_cast<std::int64_t>(n));
      r.octets(8 * n, "polygonalRegion");
      break;
    }
    case 3: {
      const std::size_t n = r.quantity("identifiedRegion");
      for (std::size_t i = 0; i < n && r.ok(); ++i)
        get_identified_region(r);
      break;
    }
    default:
      r.open_type("GeographicRegion");
      break;
  }
}

void get_encryption_key(CoerReader& r) {
  r.enumerated(0, "supportedSymmAlg");  // aes128Ccm is the only root value
  const unsigned tag = r.choice_tag("BasePublicEncryptionKey");
  if (!r.ok())
    return;
  if (tag <= 1) {
    EccP256CurvePoint p;
    get_point(r, p, "BasePublicEncryptionKey");
  } else {
    r.open_type("BasePublicEncryptionKey");
  }
}

/// Copies what @p get read into @p out as octets.
template <typename Get>
void keep_octets(CoerReader& r, Bytes& out, Get get) {
  const std::size_t from = r.offset();
  get();
  auto b = r.consumed_since(from);
  out.assign(b.begin(), b.end());
}

/// @p key_from / @p key_to get the reader's offsets around the verification key's point.
void get_tbs_certificate(CoerReader& r, ToBeSignedCertificate& t, std::size_t* key_from = nullptr,
                         std::size_t* key_to = nullptr) {
  bool ext = false;
  const std::uint32_t flags = r.preamble(true, &ext, 7, "ToBeSignedCertificate");
  const unsigned id = r.choice_tag("CertificateId");
  if (!r.ok())
    return;
  switch (id) {
    case 0:
      t.id.kind = CertificateId::Kind::kLinkageData;
      keep_octets(r, t.id.value, [&] {
        const bool group = r.preamble(false, nullptr, 1, "LinkageData") != 0;
        r.u16("iCert");
        r.octets(9, "linkage-value");
        if (group)
          r.octets(13, "group-linkage-value");
      });
      break;
    case 1:
    case 2: {
      t.id.kind = id == 1 ? CertificateId::Kind::kName : CertificateId::Kind::kBinaryId;
      auto b = r.var_octets("CertificateId");
      if (r.ok() && (id == 1 ? b.size() > 255 : (b.empty() || b.size() > 64)))
        r.fail(Error::kSizeOutOfRange, "CertificateId", static_cast<std::int64_t>(b.size()));
      t.id.value.assign(b.begin(), b.end());
      break;
    }
    case 3:
      t.id.kind = CertificateId::Kind::kNone;
      break;
    default:
      unsupported_alternative(r, id, "CertificateId");
      return;
  }
  r.fixed(t.craca_id, "cracaId");
  t.crl_series = r.u16("crlSeries");
  t.validity.start = r.u32("validityPeriod.start");
  const unsigned unit = r.choice_tag("validityPeriod.duration");
  if (r.ok() && unit > 6)
    r.fail(Error::kValueOutOfRange, "validityPeriod.duration", unit);
  t.validity.unit = static_cast<DurationUnit>(unit);
  t.validity.duration = r.u16("validityPeriod.duration");
  if ((flags & 0x40u) != 0)
    keep_octets(r, t.region.emplace(), [&] { get_region(r); });
  if ((flags & 0x20u) != 0)
    t.assurance_level = r.u8("assuranceLevel");
  if ((flags & 0x10u) != 0) {
    const std::size_t n = r.quantity("appPermissions");
    auto& v = t.app_permissions.emplace();
    for (std::size_t i = 0; i < n && r.ok(); ++i)
      get_psid_ssp(r, v.emplace_back());
  }
  auto get_perms = [&](std::uint32_t bit, std::optional<std::vector<PsidGroupPermissions>>& perms,
                       const char* name) {
    if ((flags & bit) == 0)
      return;
    const std::size_t n = r.quantity(name);
    auto& v = perms.emplace();
    for (std::size_t i = 0; i < n && r.ok(); ++i)
      get_group_permissions(r, v.emplace_back());
  };
  get_perms(0x08u, t.cert_issue_permissions, "certIssuePermissions");
  get_perms(0x04u, t.cert_request_permissions, "certRequestPermissions");
  t.can_request_rollover = (flags & 0x02u) != 0;
  if ((flags & 0x01u) != 0)
    keep_octets(r, t.encryption_key.emplace(), [&] { get_encryption_key(r); });
  const unsigned vki = r.choice_tag("verifyKeyIndicator");
  if (!r.ok())
    return;
  if (vki != 0) {
    // reconstructionValue belongs to implicit certificates, which TS 103 097 does not use.
    r.fail(Error::kUnsupported, "verifyKeyIndicator", vki);
    return;
  }
  const unsigned curve = r.choice_tag("PublicVerificationKey");
  if (!r.ok())
    return;
  if (curve > 1) {
    unsupported_alternative(r, curve, "PublicVerificationKey");
    return;
  }
  t.verify_key.curve = static_cast<EccCurve>(curve);
  if (key_from)
    *key_from = r.offset();
  get_point(r, t.verify_key.point, "verificationKey");
  if (key_to)
    *key_to = r.offset();
  if (ext && r.ok()) {
    std::size_t present = 0;
    r.extension_bitmap(0, &present, "ToBeSignedCertificate extensions");
    r.skip_open_types(present, "ToBeSignedCertificate extension");
  }
}

void get_certificate(CoerReader& r, Certificate& c) {
  const std::size_t from = r.offset();
  const bool has_signature = r.preamble(false, nullptr, 1, "Certificate") != 0;
  const std::uint8_t version = r.u8("Certificate.version");
  if (r.ok() && version != 3) {
    r.fail(Error::kUnsupportedVersion, "Certificate.version", version);
    return;
  }
  const unsigned type = r.enumerated(1, "Certificate.type");
  if (r.ok() && type != 0) {
    r.fail(Error::kUnsupported, "Certificate.type (implicit)", type);
    return;
  }
  const unsigned issuer = r.choice_tag("IssuerIdentifier");
  if (!r.ok())
    return;
  switch (issuer) {
    case 0:
      c.issuer.kind = IssuerIdentifier::Kind::kSha256AndDigest;
      r.fixed(c.issuer.digest, "sha256AndDigest");
      break;
    case 1:
      c.issuer.kind = IssuerIdentifier::Kind::kSelf;
      c.issuer.self_hash = static_cast<HashAlgorithm>(r.enumerated(1, "IssuerIdentifier.self"));
      break;
    case 2:
      c.issuer.kind = IssuerIdentifier::Kind::kSha384AndDigest;
      in_open_type(r, "sha384AndDigest",
                   [&](CoerReader& ir) { ir.fixed(c.issuer.digest, "sha384AndDigest"); });
      break;
    default:
      unsupported_alternative(r, issuer, "IssuerIdentifier");
      return;
  }
  // 1609.2 6.4.3: the issuer signs the COER octets of toBeSigned; they are kept as received
  // (COER is canonical and the reader enforces it), extension additions it skips included.
  const std::size_t tbs_from = r.offset();
  std::size_t key_from = 0;
  std::size_t key_to = 0;
  get_tbs_certificate(r, c.tbs, &key_from, &key_to);
  const std::size_t tbs_to = r.offset();
  if (has_signature)
    get_signature(r, c.signature.emplace());
  if (r.ok()) {
    auto b = r.consumed_since(from);
    c.encoding.assign(b.begin(), b.end());
    c.tbs_offset = tbs_from - from;
    c.tbs_length = tbs_to - tbs_from;
    c.key_offset = key_from - from;
    c.key_length = key_to - key_from;
  }
}

void get_header(CoerReader& r, HeaderInfo& h) {
  bool ext = false;
  const std::uint32_t flags = r.preamble(true, &ext, 6, "HeaderInfo");
  h.psid = r.unsigned_integer("psid");
  if ((flags & 0x20u) != 0)
    h.generation_time = r.u64("generationTime");
  if ((flags & 0x10u) != 0)
    h.expiry_time = r.u64("expiryTime");
  if ((flags & 0x08u) != 0) {
    auto& l = h.generation_location.emplace();
    l.latitude = r.i32("generationLocation.latitude");
    l.longitude = r.i32("generationLocation.longitude");
    l.elevation = r.u16("generationLocation.elevation");
    // NinetyDegreeInt / OneEightyDegreeInt ranges (1609.2 6.4.27..).
    if (r.ok() && (l.latitude < -900000000 || l.latitude > 900000001))
      r.fail(Error::kValueOutOfRange, "generationLocation.latitude", l.latitude);
    if (r.ok() && (l.longitude < -1799999999 || l.longitude > 1800000001))
      r.fail(Error::kValueOutOfRange, "generationLocation.longitude", l.longitude);
  }
  if ((flags & 0x04u) != 0)
    r.fixed(h.p2pcd_learning_request.emplace(), "p2pcdLearningRequest");
  if ((flags & 0x02u) != 0) {
    bool crl_ext = false;
    r.preamble(true, &crl_ext, 0, "MissingCrlIdentifier");
    auto& m = h.missing_crl_identifier.emplace();
    r.fixed(m.craca_id, "cracaId");
    m.crl_series = r.u16("crlSeries");
    if (crl_ext && r.ok()) {
      std::size_t present = 0;
      r.extension_bitmap(0, &present, "MissingCrlIdentifier extensions");
      r.skip_open_types(present, "MissingCrlIdentifier extension");
    }
  }
  if ((flags & 0x01u) != 0) {
    r.fail(Error::kUnsupported, "HeaderInfo.encryptionKey");  // no CAM or DENM carries one
    return;
  }
  if (!ext || !r.ok())
    return;
  std::size_t present = 0;
  const std::uint32_t known = r.extension_bitmap(2, &present, "HeaderInfo extensions");
  std::size_t known_present = 0;
  if ((known & 2u) != 0) {
    ++known_present;
    in_open_type(r, "inlineP2pcdRequest", [&](CoerReader& ir) {
      get_hashed_id3s(ir, h.inline_p2pcd_request.emplace(), "inlineP2pcdRequest");
    });
  }
  if ((known & 1u) != 0) {
    ++known_present;
    in_open_type(r, "requestedCertificate",
                 [&](CoerReader& ir) { get_certificate(ir, h.requested_certificate.emplace()); });
  }
  // Later additions (1609.2-2022: pduFunctionalType, contributedExtensions) are skipped.
  r.skip_open_types(present - known_present, "HeaderInfo extension");
}

void get_data(CoerReader& r, Ieee1609Dot2Data& d) {
  const std::uint8_t version = r.u8("Ieee1609Dot2Data.protocolVersion");
  if (r.ok() && version != kIeee1609Dot2ProtocolVersion) {
    r.fail(Error::kUnsupportedVersion, "Ieee1609Dot2Data.protocolVersion", version);
    return;
  }
  const unsigned content = r.choice_tag("Ieee1609Dot2Content");
  if (!r.ok())
    return;
  if (content == 0) {
    d.content = Ieee1609Dot2Data::Content::kUnsecuredData;
    auto b = r.var_octets("unsecuredData");
    d.unsecured_data.assign(b.begin(), b.end());
    return;
  }
  if (content != 1) {
    // encryptedData, signedCertificateRequest: not used for CAM or DENM.
    r.fail(Error::kUnsupported, "Ieee1609Dot2Content", content);
    return;
  }
  d.content = Ieee1609Dot2Data::Content::kSignedData;
  auto& s = d.signed_data;
  s.hash_id = static_cast<HashAlgorithm>(r.enumerated(1, "hashId"));
  const std::size_t tbs_from = r.offset();
  bool payload_ext = false;
  const std::uint32_t payload = r.preamble(true, &payload_ext, 2, "SignedDataPayload");
  if (r.ok() && payload == 0) {
    // 1609.2 6.3.7: at least one of data and extDataHash.
    r.fail(Error::kValueOutOfRange, "SignedDataPayload (empty)");
    return;
  }
  if ((payload & 2u) != 0) {
    const std::uint8_t inner_version = r.u8("payload.data.protocolVersion");
    if (r.ok() && inner_version != kIeee1609Dot2ProtocolVersion) {
      r.fail(Error::kUnsupportedVersion, "payload.data.protocolVersion", inner_version);
      return;
    }
    const unsigned inner = r.choice_tag("payload.data.content");
    if (r.ok() && inner != 0) {
      // TS 103 097 7.1: CAM and DENM sign unsecuredData; nesting is not followed.
      r.fail(Error::kUnsupported, "payload.data.content", inner);
      return;
    }
    auto b = r.var_octets("payload.data.unsecuredData");
    s.tbs.payload.data.emplace(b.begin(), b.end());
  }
  if ((payload & 1u) != 0) {
    const unsigned h = r.choice_tag("extDataHash");
    if (r.ok() && h != 0) {
      unsupported_alternative(r, h, "extDataHash");
      return;
    }
    r.fixed(s.tbs.payload.ext_data_hash.emplace(), "extDataHash");
  }
  if (payload_ext && r.ok()) {
    std::size_t present = 0;
    r.extension_bitmap(0, &present, "SignedDataPayload extensions");
    r.skip_open_types(present, "SignedDataPayload extension");
  }
  get_header(r, s.tbs.header);
  if (r.ok()) {
    auto b = r.consumed_since(tbs_from);
    s.tbs_encoding.assign(b.begin(), b.end());
  }
  const unsigned signer = r.choice_tag("SignerIdentifier");
  if (!r.ok())
    return;
  switch (signer) {
    case 0:
      s.signer.kind = SignerIdentifier::Kind::kDigest;
      r.fixed(s.signer.digest, "signer.digest");
      break;
    case 1: {
      s.signer.kind = SignerIdentifier::Kind::kCertificate;
      const std::size_t n = r.quantity("signer.certificate");
      if (r.ok() && n == 0)
        r.fail(Error::kSizeOutOfRange, "signer.certificate", 0);
      for (std::size_t i = 0; i < n && r.ok(); ++i)
        get_certificate(r, s.signer.certificates.emplace_back());
      break;
    }
    case 2:
      s.signer.kind = SignerIdentifier::Kind::kSelf;
      break;
    default:
      unsupported_alternative(r, signer, "SignerIdentifier");
      return;
  }
  get_signature(r, s.signature);
}

}  // namespace

namespace coer {
void put(CoerWriter& w, const Certificate& c) {
  put_certificate(w, c);
}
void put(CoerWriter& w, const ToBeSignedData& t) {
  put_tbs_data(w, t);
}
void put(CoerWriter& w, const Signature& s) {
  w.choice_tag(static_cast<unsigned>(s.curve));
  put_point(w, s.r);
  w.octets(s.s);
}
void put(CoerWriter& w, const EccP256CurvePoint& p) {
  put_point(w, p);
}
void get(CoerReader& r, Certificate& c) {
  get_certificate(r, c);
}
}  // namespace coer

Expected<Ieee1609Dot2Data, asn1::CodecError> decode_data_prefix(std::span<const std::uint8_t> bytes,
                                                                std::size_t* consumed) {
  CoerReader r(bytes);
  Ieee1609Dot2Data d;
  get_data(r, d);
  if (!r.ok())
    return Unexpected<asn1::CodecError>{r.error()};
  *consumed = r.offset();
  return d;
}

Expected<Ieee1609Dot2Data, asn1::CodecError> decode_data(std::span<const std::uint8_t> bytes) {
  CoerReader r(bytes);
  Ieee1609Dot2Data d;
  get_data(r, d);
  r.expect_end("Ieee1609Dot2Data");
  if (!r.ok())
    return Unexpected<asn1::CodecError>{r.error()};
  return d;
}

Expected<Certificate, asn1::CodecError> decode_certificate(std::span<const std::uint8_t> bytes) {
  CoerReader r(bytes);
  Certificate c;
  get_certificate(r, c);
  r.expect_end("Certificate");
  if (!r.ok())
    return Unexpected<asn1::CodecError>{r.error()};
  return c;
}

Bytes encode(const Ieee1609Dot2Data& data) {
  Bytes out;
  CoerWriter w(out);
  put_data(w, data);
  return out;
}

Bytes encode(const Certificate& cert) {
  Bytes out;
  CoerWriter w(out);
  put_certificate(w, cert);
  return out;
}

Bytes encode(const ToBeSignedData& tbs) {
  Bytes out;
  CoerWriter w(out);
  put_tbs_data(w, tbs);
  return out;
}

Bytes encode(const ToBeSignedCertificate& tbs) {
  Bytes out;
  CoerWriter w(out);
  put_tbs_certificate(w, tbs);
  return out;
}

}  // namespace tb::its::security
