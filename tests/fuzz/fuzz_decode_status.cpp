// libFuzzer target: the controller's status and attitude decoders and its
// handler, as pointing_controller runs them: bytes -> gimbal_status_t /
// gimbal_attitude_t (whole message or dropped) -> answerStatus. Input:
// records of [u8 length][u8 kind] + length bytes. Checks, beyond the
// sanitizers (UBSan catches any seq overflow): the command answers the
// status it was given and its seq never goes backwards.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "gimbalsim/controllers/answer.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/gimbal_attitude_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"

namespace gc = gimbalsim::controllers;
namespace fw = gimbalsim::contract;  // the message contract

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const gc::ControllerConfig* config =
      new gc::ControllerConfig(gc::loadControllerConfig(std::string(GIMBALSIM_CONTROLLER_CONFIG), {}));
  gc::ControllerState state;
  fw::Attitude attitude{.seq = -1};
  std::int64_t next_seq = 0;
  std::size_t pos = 0;
  while (pos + 2 <= size) {
    const std::size_t len = data[pos];
    const bool is_status = (data[pos + 1] & 1) != 0;
    pos += 2;
    const std::size_t n = len < size - pos ? len : size - pos;
    std::vector<std::uint8_t> bytes(data + pos, data + pos + n);  // exactly n bytes for ASan
    pos += n;
    if (is_status) {
      gimbalsim::gimbal_status_t m{};
      if (m.decode(bytes.data(), 0, static_cast<int>(n)) != static_cast<int>(n)) continue;
      fw::Status st;
      fw::copyFields<fw::StatusFields>(st, m);
      const std::int64_t before = next_seq;
      const gc::Answer ans = gc::answerStatus(*config, state, st, attitude, next_seq);
      if (ans.cmd.status_seq != st.seq || ans.cmd.seq < before || next_seq < ans.cmd.seq) std::abort();
    } else {
      gimbalsim::gimbal_attitude_t m{};
      if (m.decode(bytes.data(), 0, static_cast<int>(n)) != static_cast<int>(n)) continue;
      fw::copyFields<fw::AttitudeFields>(attitude, m);
    }
  }
  return 0;
}
