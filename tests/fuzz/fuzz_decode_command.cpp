// libFuzzer target: the command decoder and handler, as firmware_sim runs
// them: bytes -> gimbal_command_t (lcm-gen's decoder, the bridge's rule:
// the whole message or undecodable) -> Firmware::receive with a source ->
// ticks. Input: records of [u8 length][u8 source][u8 ticks] + length bytes;
// the first 8 bytes of a record, when the record is long enough, are the
// whole message only if the decoder says so. Oracle: a shadow firmware that
// receives only the commands the first one accepted must stay identical bit
// for bit (rejected commands change nothing); applied torque finite and
// within the limit; the seq reported never comes from a refused command.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "gimbalsim/firmware_sim/firmware.hpp"
#include "gimbalsim/gimbal_command_t.hpp"

namespace fw = gimbalsim::firmware;
using Bench = gimbalsim::FixedIdeal;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const fw::PlantScene* scene = new fw::PlantScene(
      fw::loadPlantScene(std::string(GIMBALSIM_SCENES_DIR) + "/paper_ideal.yaml", {"structure.base=fixed"}));
  fw::Config c;
  c.watchdog_timeout = 0.005;  // 5 ticks: bindings expire within a fuzz input
  fw::Firmware<Bench> a(*scene, c), shadow(*scene, c);
  std::size_t pos = 0;
  std::int64_t utime = 0;
  a.tick(utime);
  shadow.tick(utime);
  while (pos + 3 <= size) {
    const std::size_t len = data[pos];
    const fw::SourceId src = data[pos + 1] & 3u;
    const int ticks = data[pos + 2] & 7;
    pos += 3;
    const std::size_t n = len < size - pos ? len : size - pos;
    std::vector<std::uint8_t> bytes(data + pos, data + pos + n);  // exactly n bytes for ASan
    pos += n;
    gimbalsim::gimbal_command_t m;
    const int used = m.decode(bytes.data(), 0, static_cast<int>(n));
    if (used < 0 || used != static_cast<int>(n)) {
      a.receiveUndecodable();
    } else {
      fw::Command cmd;
      fw::copyFields<fw::CommandFields>(cmd, m);
      const std::int64_t before = a.lastAcceptedSeq();
      if (a.receive(cmd, src) == fw::Rejection::None) {
        if (shadow.receive(cmd, src) != fw::Rejection::None) std::abort();  // same history: same verdict
      } else if (a.lastAcceptedSeq() != before) {
        std::abort();
      }
    }
    for (int k = 0; k < ticks; ++k) {
      utime += 1000;
      a.tick(utime);
      shadow.tick(utime);
      const fw::Status& s = a.status();
      for (int j = 0; j < 2; ++j) {
        if (!std::isfinite(s.applied_torque[j]) || std::fabs(s.applied_torque[j]) > scene->scene.run.torque_limit(j)) {
          std::abort();
        }
      }
      if (!(a.state().q == shadow.state().q) || !(a.state().v == shadow.state().v)) std::abort();
      if (s.applied_torque[0] != shadow.status().applied_torque[0]) std::abort();
    }
  }
  return 0;
}
