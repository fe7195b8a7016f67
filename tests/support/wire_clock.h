#pragma once

// A second receiver of a test's UDP stream: the sender's own clock read off the wire, as an oracle
// for what acrolab's live sources measure (it shares no code with them).

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "acro/capture/live_source.h"

namespace acro::testing {

// The sender's clock, read off the wire: every datagram on a UDP port of the test's own is
// searched for the start of a video picture (an MPEG-TS packet that starts a PES of stream 0xE0–
// 0xEF with a PTS) and its arrival noted (LiveClockNow). Stream time τ (from the first picture's
// PTS) was sent at τ + origin(), where origin is the 95th percentile of arrival − τ over the
// pictures (with B-frames, pictures are sent in decoding order, ahead of their time; the latest
// are sent at it).
class WireClock {
 public:
  explicit WireClock(int port) : port_(port) {
    fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    bound_ = fd_ >= 0 && ::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    timeval tv{0, 100000};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    thread_ = std::thread([this] { Receive(); });
  }
  ~WireClock() {
    done_ = true;
    thread_.join();
    ::close(fd_);
  }
  bool bound() const { return bound_; }
  int port() const { return port_; }
  int pictures() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return static_cast<int>(lateness_.size());
  }
  double origin() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::vector<double> v = lateness_;
    if (v.empty()) return NAN;
    const size_t k = std::min(v.size() - 1, static_cast<size_t>(0.95 * double(v.size())));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
  }

 private:
  void Receive() {
    std::uint8_t d[65536];
    while (!done_.load()) {
      const ssize_t n = ::recv(fd_, d, sizeof d, 0);
      if (n <= 0) continue;
      const double now = capture::LiveClockNow();
      for (ssize_t at = 0; at + 188 <= n; at += 188) {
        const std::uint8_t* ts = d + at;
        if (ts[0] != 0x47 || !(ts[1] & 0x40)) continue;  // sync byte, payload unit start
        int payload = 4;
        if (ts[3] & 0x20) payload += 1 + ts[4];  // adaptation field
        if (!(ts[3] & 0x10) || payload + 14 > 188) continue;
        const std::uint8_t* pes = ts + payload;
        if (pes[0] != 0 || pes[1] != 0 || pes[2] != 1 || (pes[3] & 0xF0) != 0xE0) continue;
        if (!(pes[7] & 0x80)) continue;  // no PTS
        const std::int64_t pts = (std::int64_t(pes[9] & 0x0E) << 29) |
                                 (std::int64_t(pes[10]) << 22) |
                                 (std::int64_t(pes[11] & 0xFE) << 14) |
                                 (std::int64_t(pes[12]) << 7) | (std::int64_t(pes[13]) >> 1);
        const std::lock_guard<std::mutex> lock(mutex_);
        if (first_pts_ < 0) first_pts_ = pts;
        lateness_.push_back(now - double(pts - first_pts_) / 90000.0);
      }
    }
  }
  int port_ = -1;
  int fd_ = -1;
  bool bound_ = false;
  std::atomic<bool> done_{false};
  mutable std::mutex mutex_;
  std::int64_t first_pts_ = -1;
  std::vector<double> lateness_;
  std::thread thread_;
};

}  // namespace acro::testing
