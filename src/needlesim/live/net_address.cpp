#include "needlesim/live/net_address.hpp"

#include <arpa/inet.h>

#include "needlesim/core/error.hpp"

namespace needlesim::live {

sockaddr_in socketAddress(const std::string& host, int port, const std::string& hostOption, const std::string& portOption) {
  if (port < 0 || port > 65535)
    throw InputError(commandLine(), portOption, std::to_string(port), "is not a port number", "0 (any free port) to 65535");
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  const std::string ip = host == "localhost" ? "127.0.0.1" : host;
  if (inet_pton(AF_INET, ip.c_str(), &a.sin_addr) != 1)
    throw InputError(commandLine(), hostOption, host, "is not an IPv4 address",
                     "127.0.0.1 (this machine only, the default), localhost, 0.0.0.0 (every interface) or an address of this machine");
  return a;
}

}  // namespace needlesim::live

namespace needlesim::live {

bool isLoopback(const std::string& host) {
  if (host == "localhost") return true;
  in_addr a{};
  return inet_pton(AF_INET, host.c_str(), &a) == 1 && (ntohl(a.s_addr) >> 24) == 127;
}

}  // namespace needlesim::live
