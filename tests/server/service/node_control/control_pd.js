// A controller in another language (issue 45: "the .proto is the contract"): Node with
// @grpc/grpc-js, the messages loaded at run time from proto/mbstream/v1/*.proto by
// @grpc/proto-loader. It starts a run of the IRB 1600 whose six joints are driven from here
// by effort, and answers every state with the seed servo's PD law (the same law the C++ test
// ControlServiceTest.ExternalSeedServoEqualsBuiltInSampledServo sends).
//
//   node control_pd.js ADDRESS SPEC_JSON
//
// SPEC_JSON is the built-in sampled servo's RunSpec in protobuf's JSON mapping with the proto
// field names (preserve_proto_field_names); the script
// turns each pd_servo drive into an external effort drive of the same period. It prints
// "run ID" then, at the end, "ended STATE steps N"; exit 0 when the run FINISHED.
'use strict';
const path = require('path');
const fs = require('fs');
const grpc = require('@grpc/grpc-js');
const protoLoader = require('@grpc/proto-loader');

const [address, specFile] = process.argv.slice(2);
if (!address || !specFile) {
  console.error('usage: node control_pd.js ADDRESS SPEC_JSON');
  process.exit(2);
}
const protoRoot = path.resolve(__dirname, '../../../../proto');
const definition = protoLoader.loadSync('mbstream/v1/simulation_service.proto', {
  includeDirs: [protoRoot],
  keepCase: true,
  longs: Number,
  enums: String,
  defaults: true,
  oneofs: true,
});
const v1 = grpc.loadPackageDefinition(definition).mbstream.v1;
const client = new v1.Simulation(address, grpc.credentials.createInsecure());

const servo = JSON.parse(fs.readFileSync(specFile, 'utf8'));
const laws = servo.drives.map((d) => d.pd_servo);
const period = laws[0].period_s;
// The spec as the stream's start sends it: the JSON (proto field names) with each drive an
// external effort drive of the servo's period.
const spec = Object.assign({}, servo, {
  drives: laws.map(() => ({ external: { command: 'effort', period_s: period } })),
});

// kp (q_ref - q) + kd (qd_ref - qd), q_ref = offset + sum a sin(w t + phase), in the same
// order of operations as the server's DriveSet (bit for bit: the test compares to 1e-12).
function effort(state) {
  return laws.map((law, i) => {
    const sines = law.trajectory.sum_of_sines;
    let value = sines.offset ?? 0;
    let rate = 0;
    for (const term of sines.terms || []) {
      const arg = term.omega * state.t_s + (term.phase ?? 0);
      value += term.amplitude * Math.sin(arg);
      rate += (term.amplitude * term.omega) * Math.cos(arg);
    }
    return law.kp * (value - state.q[i]) + law.kd * (rate - state.qd[i]);
  });
}

const call = client.Control();
let steps = 0;
let ended = null;
call.on('data', (response) => {
  if (response.started) {
    console.log('run ' + response.started.run.id);
  } else if (response.state) {
    if (response.state.final) return;
    call.write({ command: { step: response.state.step, values: effort(response.state) } });
    steps += 1;
  } else if (response.ended) {
    ended = response.ended;
    call.end();
  }
});
call.on('error', (error) => {
  console.error('Control failed: ' + error.code + ' ' + error.details);
  process.exit(1);
});
call.on('end', () => {
  const state = ended ? ended.state : 'none';
  console.log('ended ' + state + ' steps ' + steps);
  process.exit(state === 'FINISHED' ? 0 : 1);
});
call.write({ start: { model: 'irb1600', spec } });
