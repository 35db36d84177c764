#pragma once
// The address a server binds: an IPv4 address (127.0.0.1 unless the user names another).
#include <netinet/in.h>

#include <string>

namespace needlesim::live {

// `host` ("localhost" or dotted IPv4) and `port` as a socket address; InputError naming
// `hostOption` or `portOption` for a host that is no IPv4 address or a port out of range.
sockaddr_in socketAddress(const std::string& host, int port, const std::string& hostOption, const std::string& portOption);

}  // namespace needlesim::live

namespace needlesim::live {

// Whether `host` ("localhost" or dotted IPv4) is this machine only (127.0.0.0/8).
bool isLoopback(const std::string& host);

}  // namespace needlesim::live
