// What the tests' publishers put in their samples, checked member by member in every message a reader decodes:
// contentChecks(...)[schema name](decoded value, { publishTime } or {}, the channel's previous value) is undefined
// when the value is right, else what is wrong.
export function contentChecks({ sensor }) {
  return {
    // tm-robot-sim: generated_ns is the source timestamp (an MCAP message's publish time), sequence numbers count
    // up (with gaps where the gateway dropped samples).
    "tgw::idl::PaperMessage": (value, message, previous) => {
      if (message.publishTime !== undefined && BigInt(value.generated_ns) !== message.publishTime) {
        return `generated_ns ${value.generated_ns} is not the publish time ${message.publishTime}`;
      }
      if (previous && value.sequence_number <= previous.sequence_number) {
        return `sequence_number ${value.sequence_number} after ${previous.sequence_number}`;
      }
      if (value.data.length === 0) return "no data";
      return undefined;
    },
    // The gateway under test runs --sensor SENSOR (any, when undefined).
    "tgw::idl::GatewayStatus": (value) =>
      (sensor === undefined || value.sensor === sensor) && value.gateway_prefix.length === 12 &&
      Array.isArray(value.topics)
        ? undefined
        : `sensor '${value.sensor}' (expected '${sensor}'), ${value.gateway_prefix.length} prefix bytes`,
    // test/idl/announced_types_publisher.
    "tgw_test::FlatReading": (value) =>
      value.ok === true && value.label === "left wheel" && value.unit === "rad/s" &&
      value.f64 === 20.5 + value.sensor_id && value.grid.length === 2 && value.grid[1].length === 3
        ? undefined
        : `sensor_id ${value.sensor_id}, ok ${value.ok}, label '${value.label}', unit '${value.unit}', f64 ${value.f64}`,
  };
}
