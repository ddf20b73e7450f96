#include "lcm_bridge.hpp"

#include "gimbalsim/gimbal_antenna_t.hpp"
#include "gimbalsim/gimbal_attitude_t.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_loop_stats_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"
#include "gimbalsim/gimbal_truth_t.hpp"
#include "realtime.hpp"

namespace gimbalsim::firmware {

static_assert(int{kWatchdogTripped} == int{gimbal_status_t::FAULT_WATCHDOG_TRIPPED});
static_assert(int{kTorqueSaturated} == int{gimbal_status_t::FAULT_TORQUE_SATURATED});
static_assert(int{kCommandRejected} == int{gimbal_status_t::FAULT_COMMAND_REJECTED});
static_assert(int{kPlantFault} == int{gimbal_status_t::FAULT_PLANT_FAULT});
static_assert(int{kLockstepTimeout} == int{gimbal_status_t::FAULT_LOCKSTEP_TIMEOUT});
static_assert(kModeOff == gimbal_command_t::MODE_OFF && kModeTorque == gimbal_command_t::MODE_TORQUE);

LcmBridge::LcmBridge(lcm_wire::UdpmSender& tx, lcm_wire::UdpmReceiver& rx, Channels ch)
    : tx_(tx), rx_(rx), ch_(std::move(ch)) {
  for (auto& x : pub_seq_) x = -1;
  for (auto& t : pub_ns_) t = 0;
}

lcm_wire::ReassemblyLimits LcmBridge::receiveLimits() {
  lcm_wire::ReassemblyLimits l;
  l.max_message_bytes = 4096;  // gimbal_command_t is 49 bytes; room for another sender's fragmenting
  l.max_partials = 4;
  l.max_fragments = 64;
  l.partial_timeout_ns = 100000000;
  return l;
}

void LcmBridge::drain() {
  rx_.drain([this](const lcm_wire::Message& m, std::int64_t) { onCommand(m); }, kDrainMax);
}

bool LcmBridge::receive(int timeout_ms, std::int64_t spin_ns) {
  return rx_.waitDrain(timeout_ms, spin_ns, [this](const lcm_wire::Message& m, std::int64_t) { onCommand(m); },
                       kDrainMax) >= 0;
}

void LcmBridge::onCommand(const lcm_wire::Message& msg) {
  const std::int64_t now = nowNs();
  Inbound m;
  m.source = msg.source.id();
  gimbal_command_t c;
  const int size = static_cast<int>(msg.size);  // <= receiveLimits().max_message_bytes
  const int n = c.decode(msg.data, 0, size);
  if (n < 0 || n != size) {
    m.undecodable = true;  // garbage, a wrong type (fingerprint mismatch) or trailing bytes
  } else {
    copyFields<CommandFields>(m.cmd, c);
    // Round trip: the first answer to a status we published.
    const std::size_t i = static_cast<std::size_t>(c.status_seq) % kRoundTripSlots;
    if (c.status_seq >= 0 && pub_seq_[i] == c.status_seq) {
      roundtrip.add(static_cast<double>(now - pub_ns_[i]) * 1e-3);
      pub_seq_[i] = -1;
    }
  }
  if (sink_ == nullptr || !sink_->take(m)) ++dropped_in;
}

void LcmBridge::publish(const Status& s) {
  gimbal_status_t o;
  copyFields<StatusFields>(o, s);
  tx_.stageMessage(ch_.status, o);
  const std::size_t i = static_cast<std::size_t>(s.seq) % kRoundTripSlots;
  pub_seq_[i] = s.seq;
  unsent_slot_ = static_cast<int>(i);  // stamped when it is sent: the round trip starts at the wire, not here
  last_status_ = s;
}

void LcmBridge::publish(const Truth& t) {
  gimbal_truth_t o;
  copyFields<TruthFields>(o, t);
  tx_.stageMessage(ch_.truth, o);
}

void LcmBridge::publish(const Attitude& a) {
  gimbal_attitude_t o;
  copyFields<AttitudeFields>(o, a);
  tx_.stageMessage(ch_.attitude, o);
}

void LcmBridge::publish(const Antenna& a) {
  gimbal_antenna_t o;
  copyFields<AntennaFields>(o, a);
  tx_.stageMessage(ch_.antenna, o);
}

void LcmBridge::publishStats(std::int64_t utime, const LoopStats& st, bool realtime, bool lockstep) {
  gimbal_loop_stats_t o;
  o.utime = utime;
  o.ticks = st.ticks.load();
  o.period_p50 = st.period.quantile(0.5);
  o.period_p99 = st.period.quantile(0.99);
  o.period_p999 = st.period.quantile(0.999);
  o.period_max = st.period.max();
  o.lateness_p50 = st.lateness.quantile(0.5);
  o.lateness_p99 = st.lateness.quantile(0.99);
  o.lateness_p999 = st.lateness.quantile(0.999);
  o.lateness_max = st.lateness.max();
  o.compute_p50 = st.compute.quantile(0.5);
  o.compute_p99 = st.compute.quantile(0.99);
  o.compute_max = st.compute.max();
  o.overruns = st.overruns.load();
  o.late_ticks = st.late_ticks.load();
  o.roundtrip_p50 = roundtrip.quantile(0.5);
  o.roundtrip_p99 = roundtrip.quantile(0.99);
  o.roundtrip_p999 = roundtrip.quantile(0.999);
  o.roundtrip_max = roundtrip.max();
  o.substeps_mean = st.substepsMean();
  o.substeps_max = st.substeps_max.load();
  o.commands_received = last_status_.commands_received;
  o.commands_rejected = last_status_.commands_rejected;
  o.commands_missed = last_status_.commands_missed;
  o.realtime = realtime ? 1 : 0;
  o.lockstep = lockstep ? 1 : 0;
  tx_.stageMessage(ch_.loop_stats, o);
}

void LcmBridge::flush() noexcept {
  if (unsent_slot_ >= 0) {
    pub_ns_[unsent_slot_] = nowNs();
    unsent_slot_ = -1;
  }
  tx_.flush();
}

}  // namespace gimbalsim::firmware
