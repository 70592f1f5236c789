#include "network-emulator/radio/genl.hpp"

#include <linux/netlink.h>
#include <netlink/attr.h>
#include <netlink/genl/ctrl.h>
#include <netlink/genl/genl.h>
#include <netlink/msg.h>
#include <netlink/netlink.h>
#include <sys/socket.h>

#include <cstring>
#include <stdexcept>

#ifndef SOL_NETLINK
#define SOL_NETLINK 270
#endif

namespace tb::emu::radio {

void NlMsgDeleter::operator()(nl_msg* m) const {
  nlmsg_free(m);
}

std::string GenlAnswer::describe() const {
  std::string s = error < 0 ? std::strerror(-error) : "ok";
  if (!message.empty())
    s += ": " + message;
  return s;
}

GenlSocket::GenlSocket() : sock_(nl_socket_alloc()) {
  if (!sock_)
    throw std::runtime_error("generic netlink: cannot allocate a socket");
  if (int err = genl_connect(sock_); err < 0) {
    nl_socket_free(sock_);
    throw std::runtime_error(std::string("generic netlink: cannot connect: ") + nl_geterror(err));
  }
  // Ask for the kernel's reason text along with errors ("Channel is disabled", ...).
  int one = 1;
  setsockopt(nl_socket_get_fd(sock_), SOL_NETLINK, NETLINK_EXT_ACK, &one, sizeof one);
}

GenlSocket::~GenlSocket() {
  nl_socket_free(sock_);
}

std::optional<int> GenlSocket::family(const std::string& name) {
  const int id = genl_ctrl_resolve(sock_, name.c_str());
  if (id < 0)
    return std::nullopt;
  return id;
}

NlMsgPtr GenlSocket::message(int family, std::uint8_t cmd, int version, bool dump) {
  NlMsgPtr msg(nlmsg_alloc());
  if (!msg || !genlmsg_put(msg.get(), NL_AUTO_PORT, NL_AUTO_SEQ, family, 0, dump ? NLM_F_DUMP : 0,
                           cmd, static_cast<std::uint8_t>(version)))
    throw std::runtime_error("generic netlink: cannot build a message");
  return msg;
}

namespace {
struct RequestState {
  GenlAnswer answer;
  bool done = false;
  const std::function<void(nl_msg*)>* on_reply = nullptr;
};

// The extended ACK's text, if the kernel sent one (NLM_F_ACK_TLVS, NLMSGERR_ATTR_MSG). The error
// message's own header sits right before the nlmsgerr libnl hands us.
std::string extack_message(const nlmsgerr* err) {
  const auto* hdr =
      reinterpret_cast<const nlmsghdr*>(reinterpret_cast<const char*>(err) - NLMSG_HDRLEN);
  if (!(hdr->nlmsg_flags & NLM_F_ACK_TLVS) || hdr->nlmsg_len < NLMSG_HDRLEN + sizeof(nlmsgerr))
    return {};
  std::size_t offset = sizeof(nlmsgerr);
  if (!(hdr->nlmsg_flags & NLM_F_CAPPED)) {
    if (err->msg.nlmsg_len < NLMSG_HDRLEN)
      return {};
    offset += NLMSG_ALIGN(err->msg.nlmsg_len - NLMSG_HDRLEN);
  }
  const std::size_t payload = hdr->nlmsg_len - NLMSG_HDRLEN;
  if (offset >= payload)
    return {};
  auto* tlvs =
      reinterpret_cast<nlattr*>(const_cast<char*>(reinterpret_cast<const char*>(err)) + offset);
  nlattr* tb[NLMSGERR_ATTR_MAX + 1] = {};
  if (nla_parse(tb, NLMSGERR_ATTR_MAX, tlvs, static_cast<int>(payload - offset), nullptr) < 0 ||
      !tb[NLMSGERR_ATTR_MSG])
    return {};
  const char* text = static_cast<const char*>(nla_data(tb[NLMSGERR_ATTR_MSG]));
  return std::string(text, strnlen(text, static_cast<std::size_t>(nla_len(tb[NLMSGERR_ATTR_MSG]))));
}

int on_error(sockaddr_nl*, nlmsgerr* err, void* arg) {
  auto* st = static_cast<RequestState*>(arg);
  st->answer.error = err->error;
  st->answer.message = extack_message(err);
  st->done = true;
  return NL_STOP;
}
int on_ack(nl_msg*, void* arg) {
  static_cast<RequestState*>(arg)->done = true;
  return NL_STOP;
}
int on_finish(nl_msg*, void* arg) {
  static_cast<RequestState*>(arg)->done = true;
  return NL_SKIP;
}
int on_valid(nl_msg* msg, void* arg) {
  auto* st = static_cast<RequestState*>(arg);
  if (st->on_reply && *st->on_reply)
    (*st->on_reply)(msg);
  return NL_OK;
}
}  // namespace

GenlAnswer GenlSocket::request(NlMsgPtr msg, const std::function<void(nl_msg*)>& on_reply) {
  RequestState st;
  st.on_reply = &on_reply;
  // A dump ends with NLMSG_DONE; asking it for an ACK as well would leave a stray message for
  // the next request to trip over.
  if (!(nlmsg_hdr(msg.get())->nlmsg_flags & NLM_F_DUMP))
    nlmsg_hdr(msg.get())->nlmsg_flags |= NLM_F_ACK;
  std::unique_ptr<nl_cb, void (*)(nl_cb*)> cb(nl_cb_alloc(NL_CB_DEFAULT), nl_cb_put);
  nl_cb_err(cb.get(), NL_CB_CUSTOM, on_error, &st);
  nl_cb_set(cb.get(), NL_CB_ACK, NL_CB_CUSTOM, on_ack, &st);
  nl_cb_set(cb.get(), NL_CB_FINISH, NL_CB_CUSTOM, on_finish, &st);
  nl_cb_set(cb.get(), NL_CB_VALID, NL_CB_CUSTOM, on_valid, &st);
  if (int err = nl_send_auto(sock_, msg.get()); err < 0)
    return GenlAnswer{-EIO, std::string("send failed: ") + nl_geterror(err)};
  while (!st.done) {
    if (int err = nl_recvmsgs(sock_, cb.get()); err < 0 && !st.done)
      return GenlAnswer{-EIO, std::string("receive failed: ") + nl_geterror(err)};
  }
  return st.answer;
}

}  // namespace tb::emu::radio
