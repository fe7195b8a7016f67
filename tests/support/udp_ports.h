#pragma once

// UDP ports for the live tests: a port the system gives free, and a wait until a program listens
// on one (read from /proc/net/udp), so that a sender never starts before its receiver is bound
// on a busy machine.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

namespace acro::testing {

/// A UDP port on the loopback that nothing holds now (the system's choice).
inline int FreeUdpPort() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  socklen_t len = sizeof a;
  int port = -1;
  if (fd >= 0 && ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0)
    port = ntohs(a.sin_port);
  if (fd >= 0) ::close(fd);
  return port;
}

/// True once a socket of this machine is bound to UDP `port` (within `timeout_s`).
inline bool WaitForUdpListener(int port, double timeout_s) {
  char hex[8];
  std::snprintf(hex, sizeof hex, ":%04X", port);
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    for (const char* table : {"/proc/net/udp", "/proc/net/udp6"}) {
      std::ifstream in(table);
      std::string line;
      std::getline(in, line);  // the header
      while (std::getline(in, line)) {
        // "  sl  local_address rem_address ...": the local address is the second field.
        const size_t colon = line.find(':');
        if (colon == std::string::npos) continue;
        const size_t start = line.find_first_not_of(' ', colon + 1);
        const size_t stop = line.find(' ', start);
        const std::string local = line.substr(start, stop - start);
        if (local.size() >= 5 && local.compare(local.size() - 5, 5, hex) == 0) return true;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

}  // namespace acro::testing
