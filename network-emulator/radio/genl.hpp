#pragma once
/// @file Generic netlink requests (libnl-genl-3) with the kernel's own error text (extended
/// ACK), for the MAC80211_HWSIM and nl80211 families.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

struct nl_sock;
struct nl_msg;

namespace tb::emu::radio {

/// The kernel's answer to one request. hwsim answers HWSIM_CMD_NEW_RADIO with the new radio's
/// id as a positive "error", so the raw value is kept.
struct GenlAnswer {
  int error = 0;        ///< 0, a positive value (hwsim radio id) or -errno
  std::string message;  ///< the kernel's extended-ACK text, "" if none
  bool ok() const { return error >= 0; }
  /// "errno text: kernel message" for logs and exceptions.
  std::string describe() const;
};

struct NlMsgDeleter {
  void operator()(nl_msg* m) const;
};
using NlMsgPtr = std::unique_ptr<nl_msg, NlMsgDeleter>;

/// A NETLINK_GENERIC socket of the calling thread's namespace.
class GenlSocket {
 public:
  GenlSocket();
  ~GenlSocket();
  GenlSocket(const GenlSocket&) = delete;
  GenlSocket& operator=(const GenlSocket&) = delete;

  nl_sock* get() const { return sock_; }
  /// The family id of @p name, or nothing if the kernel has no such family (module not loaded).
  std::optional<int> family(const std::string& name);
  /// A message for @p family with command @p cmd (and NLM_F_DUMP when @p dump).
  NlMsgPtr message(int family, std::uint8_t cmd, int version = 1, bool dump = false);
  /// Sends @p msg and waits for the kernel's ACK; @p on_reply sees each reply message.
  GenlAnswer request(NlMsgPtr msg, const std::function<void(nl_msg*)>& on_reply = {});

 private:
  nl_sock* sock_ = nullptr;
};

}  // namespace tb::emu::radio
