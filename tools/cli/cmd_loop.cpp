// SPDX-License-Identifier: Apache-2.0
// `smoothforce loop (--scene S | --cache C | --mesh M) --method M --device D ...`
#include "cmd_loop.h"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include <smoothforce/force/force_tracking.h>
#include <smoothforce/patch/cache_file.h>
#include <smoothforce/patch/mesh_pipeline.h>
#include <smoothforce/runtime/loop_report.h>
#include <smoothforce/runtime/record_writer.h>
#include <smoothforce/runtime/scene.h>
#include <smoothforce/runtime/scripted.h>
#include <smoothforce/runtime/servo_loop.h>
#include <smoothforce/runtime/udp_device.h>
#include "cli_common.h"
#include "cli_exit.h"
#include "cli_output.h"

namespace sf::cli {
namespace {

struct LoopArgs {
  std::string scene, cache, mesh, method = "patch", device = "scripted", record;
  double rate = 1000, duration = 10, stiffness = 500, speed = 0.1, depth = 0, spinUs = 200, watchdogMs = 50;
  int patchCapacity = 256;
  rt::SafetyOptions safety;
  RefineArgs refine;
  PatchArgs patch;  ///< the patch surface of objects given as meshes (--normals, --precision, ...)
  int rtPriority = 0;
  bool depthGiven = false, json = false;
  bool paced = false;
};

void requireFinitePositive(double v, const char* option, const char* what) {
  if (!(v > 0) || !std::isfinite(v)) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    throw UsageError(std::string(option) + ": expected " + what + ", got " + buf);
  }
}

/// Optional: SCHED_FIFO at `priority` and locked memory, so page faults and other threads do
/// not delay the loop. Returns a line for the report.
std::string raisePriority(int priority) {
  if (priority <= 0) return "normal scheduling (use --rt-priority N for SCHED_FIFO)";
  sched_param p{};
  p.sched_priority = priority;
  std::string s;
  const int e = pthread_setschedparam(pthread_self(), SCHED_FIFO, &p);
  s = e == 0 ? "SCHED_FIFO priority " + std::to_string(priority)
             : "SCHED_FIFO refused (" + std::to_string(e) + "), normal scheduling";
  s += mlockall(MCL_CURRENT | MCL_FUTURE) == 0 ? ", memory locked" : ", memory not locked";
  return s;
}

nlohmann::ordered_json percentilesUs(const rt::LatencyHistogram& h) {
  return {{"p50", 1e6 * h.percentile(50)},
          {"p99", 1e6 * h.percentile(99)},
          {"p99_9", 1e6 * h.percentile(99.9)},
          {"max", 1e6 * h.max()}};
}

/// The counters of a udp device (the text report's "udp:" line).
nlohmann::ordered_json udpJson(const rt::UdpDevice& udp) {
  const rt::UdpCounters c = udp.counters();
  return {{"datagrams", c.received},
          {"accepted", c.accepted},
          {"superseded", c.superseded},
          {"duplicates", c.duplicates},
          {"out_of_order", c.outOfOrder},
          {"resyncs", c.resyncs},
          {"foreign", c.foreign},
          {"wrong_version", c.wrongVersion},
          {"malformed",
           {{"size", c.badSize},
            {"magic", c.badMagic},
            {"type", c.badType},
            {"reserved", c.badReserved},
            {"non_finite", c.nonFinite},
            {"out_of_range", c.outOfRange}}},
          {"forces_sent", c.forcesSent},
          {"send_errors", c.sendErrors}};
}

/// The report of `loop --json` (keys documented in docs/guide.md "Scripts: exit status, output, JSON"; with a udp
/// device also "udp": udpJson's counters).
nlohmann::ordered_json loopJson(const rt::Scene& scene, const rt::HapticDevice& device, const LoopArgs& a,
                                const rt::LoopStats& s, const rt::SafetyCounters& c, long long written, int status) {
  nlohmann::ordered_json objects = nlohmann::ordered_json::array();
  for (const rt::SceneObject& o : scene.objects())
    objects.push_back({{"name", o.name},
                       {"source", o.source},
                       {"faces", o.cache->numFaces()},
                       {"method", toString(o.method)},
                       {"stiffness", o.force.stiffness},
                       {"refine", toString(o.force.refine)},
                       {"angle_tolerance", o.force.angleTolerance},
                       {"max_iterations", o.force.maxIterations},
                       {"initial_guess", toString(o.force.initialGuess)},
                       {"surface_index", toString(o.force.surfaceIndex)},
                       {"final_step", toString(o.force.finalStep)},
                       {"precision", toString(o.cache->options.precision)},
                       {"normals", toString(o.cache->options.normals)},
                       {"cross_tangent", toString(o.cache->options.crossTangent)},
                       {"cage", toString(o.cache->options.cage)},
                       {"lazy", o.fromMesh}});
  nlohmann::ordered_json records = nullptr;
  if (written >= 0) records = {{"file", a.record}, {"written", written}, {"dropped", s.recordsDropped}};
  nlohmann::ordered_json j = {
      {"objects", objects},
      {"device", device.describe()},
      {"rate_hz", a.rate},
      {"duration_s", a.duration},
      {"step_compute_us", percentilesUs(s.compute)},
      {"wake_up_lateness_us", percentilesUs(s.lateness)},
      {"steps", s.steps},
      {"ticks", s.ticks},
      {"elapsed_s", s.elapsed},
      {"stopped", s.stopped},
      {"missed_deadlines", s.missedDeadlines},
      {"max_consecutive_misses", c.maxConsecutiveMisses},
      {"skipped_ticks", s.skippedTicks},
      {"contact_steps", s.contactSteps},
      {"contact_onsets", s.contactOnsets},
      {"patches_built", scene.patchesBuilt()},
      {"faces", scene.totalFaces()},
      {"safety",
       {{"clamps", c.clamps},
        {"rate_limits", c.rateLimits},
        {"non_finite", c.nonFinite},
        {"fault", c.fault == rt::Fault::None ? nullptr : nlohmann::ordered_json(toString(c.fault))},
        {"fault_time_s", c.fault == rt::Fault::None ? nullptr : nlohmann::ordered_json(c.faultTime)}}},
      {"records", records},
      {"exit_status", status}};
  if (const auto* udp = dynamic_cast<const rt::UdpDevice*>(&device)) j["udp"] = udpJson(*udp);
  return j;
}

void run(const LoopArgs& a) {
  ForceMethod method{};
  rt::LoopOptions lo;
  rt::SceneDefaults defaults;
  checkOptions([&] {  // every mistake on the command line: exit 2
    const int sources = !a.scene.empty() + !a.cache.empty() + !a.mesh.empty();
    if (sources != 1) throw UsageError("loop: give exactly one of --scene, --cache, --mesh");
    method = parseForceMethod(a.method);  // checked by its option (forceOptionCheck)
    lo.rate = a.rate;
    lo.duration = a.duration;
    lo.stop = &stopFlag();
    lo.devicePaced = a.paced;
    rt::validate(lo);
    rt::validate(a.safety);
    rt::checkScriptedSpeed(a.speed);
    if (a.depthGiven) requireFinitePositive(a.depth, "--depth", "a finite depth > 0 m");
    rt::checkDeviceSpec(a.device);
    const bool udp = a.device.rfind("udp:", 0) == 0;
    if (a.paced && !udp)
      throw UsageError("--paced: only a udp:[HOST:]PORT device paces the loop, got '" + a.device + "'");
    requireFinitePositive(a.watchdogMs, "--watchdog-ms", "a finite time > 0 ms");
    if (a.record == "-") throw UsageError("--record: give a file (standard output carries the report)");
    if (!(a.spinUs >= 0 && a.spinUs <= 1e6 / a.rate)) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "--spin-us: expected 0 .. one period (%g us), got %g", 1e6 / a.rate, a.spinUs);
      throw UsageError(buf);
    }
    defaults.method = method;
    defaults.force.stiffness = a.stiffness;
    a.refine.apply(defaults.force);
    validateForceOptions(defaults.force);
    defaults.patchOptions = a.patch.options();
    defaults.patchOptions.precision = a.refine.precision(defaults.patchOptions.precision);
    defaults.force.patchCapacity = a.patchCapacity;
  });

  const rt::RendererFactory factory = rt::sharedRendererFactory();  // a scene's copies of a mesh share it
  std::string info;  // printed once everything is set up, so that an error is the only output
  rt::Scene scene;
  if (!a.scene.empty()) {
    scene = rt::loadScene(a.scene, defaults, factory);
    for (size_t i = 0; i < scene.objects().size(); ++i)  // as with --cache: a cache keeps its options
      if (const rt::SceneObject& o = scene.objects()[i]; !o.fromMesh)
        a.patch.checkCache(*o.cache, a.scene + ": /objects/" + std::to_string(i) + " (" + o.source + ")");
  } else if (!a.cache.empty()) {
    auto cache = std::make_shared<const PatchCache>(readPatchCache(a.cache));
    a.patch.checkCache(*cache, a.cache);
    scene = rt::singleObjectScene(cache, a.cache, method, defaults.force, factory);
  } else {
    const LoadedMesh loaded = loadMesh(a.mesh, defaults.patchOptions);
    auto cache = std::make_shared<const PatchCache>(preparePatchSkeleton(loaded, defaults.patchOptions));
    scene = rt::singleObjectScene(cache, a.mesh, method, defaults.force, factory);
  }
  for (const rt::SceneObject& o : scene.objects()) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "object %s: %s, %d faces, method %s, stiffness %g N/m, refine %s (angle tol %g rad, position tol "
                  "%g of the diagonal, max %d iterations, %s start, %s index)%s\n",
                  o.name.c_str(), o.source.c_str(), o.cache->numFaces(), toString(o.method), o.force.stiffness,
                  toString(o.force.refine), o.force.angleTolerance, o.force.positionTolerance, o.force.maxIterations,
                  toString(o.force.initialGuess), toString(o.force.surfaceIndex),
                  o.fromMesh ? " (patches built lazily near the contact point)" : "");
    info += buf;
  }

  rt::ScriptOptions so;
  so.speed = a.speed;
  so.depth = a.depthGiven ? a.depth : 0;
  so.watchdog = a.watchdogMs * 1e-3;
  so.duration = a.duration;
  lo.deviceTransform = scene.deviceTransform();
  const std::unique_ptr<rt::HapticDevice> device = rt::makeDevice(a.device, scene, so);
  rt::SafetyFilter safety(a.safety);
  std::unique_ptr<rt::SpscRing<rt::StepRecord>> ring;
  std::unique_ptr<rt::RecordWriter> writer;
  if (!a.record.empty()) {
    ring = std::make_unique<rt::SpscRing<rt::StepRecord>>(size_t(1) << 15);
    writer = std::make_unique<rt::RecordWriter>(a.record, *ring);
  }
  rt::SteadyClock clock(a.spinUs * 1e-6);
  rt::ServoLoop loop(*device, scene, safety, clock, lo, ring.get());
  // The set-up lines are the text report's head; with --json they are diagnostics (stderr).
  std::FILE* head = a.json ? stderr : stdout;
  const std::string deviceText = device->describe();
  std::fputs(info.c_str(), head);
  std::fprintf(head, "device: %s\n", deviceText.c_str());
  if (!lo.deviceTransform.isIdentity())
    std::fprintf(head, "device transform: %s (device to world)\n", lo.deviceTransform.describe().c_str());
  if (a.paced)
    std::fprintf(head, "loop: device-paced (one step per sample, deadline %g ms) for %g s, %s; Ctrl-C stops\n",
                 1e3 / a.rate, a.duration, raisePriority(a.rtPriority).c_str());
  else
    std::fprintf(head, "loop: %g Hz for %g s, spin %g us, %s; Ctrl-C stops\n", a.rate, a.duration, a.spinUs,
                 raisePriority(a.rtPriority).c_str());
  std::fflush(head);

  loop.run();
  if (a.rtPriority > 0) {
    sched_param p{};
    pthread_setschedparam(pthread_self(), SCHED_OTHER, &p);
  }
  long long written = -1;
  if (writer) {
    writer->finish();
    written = writer->written();
  }
  // A latched safety fault exits 3 (also when the run was then interrupted); an interrupted
  // run 128 + signal; the report is printed either way.
  const rt::SafetyCounters& counters = safety.counters();
  const int signal = receivedSignal();
  const int status = counters.fault != rt::Fault::None ? kExitFault : signal ? 128 + signal : kExitOk;
  if (a.json) {
    printJson(stdout, loopJson(scene, *device, a, loop.stats(), counters, written, status));
    std::fputs(device->report().c_str(), stderr);  // a device's own end-of-run lines (udp: also in "udp")
  } else {
    std::fputs(
        rt::loopReport(loop.stats(), a.rate, counters, scene.patchesBuilt(), scene.totalFaces(), written).c_str(),
        stdout);
    std::fputs(device->report().c_str(), stdout);
    if (writer) std::printf("record: %s\n", a.record.c_str());
    std::fflush(stdout);
  }
  if (status == kExitFault)
    std::fprintf(stderr, "smoothforce: loop: safety fault: %s at %.3f s (force zero from then on)\n",
                 toString(counters.fault), counters.faultTime);
  else if (signal)
    std::fprintf(stderr, "smoothforce: loop: interrupted by %s; report printed\n", signalName(signal));
  setExitStatus(status);
}

}  // namespace

void addLoopCommand(CLI::App& app) {
  auto* c = app.add_subcommand("loop", "Run the real-time haptic servo loop on a scene, cache or mesh");
  auto a = std::make_shared<LoopArgs>();
  auto* scene = c->add_option("--scene", a->scene,
                              "scene file (JSON; see runtime/scene.h); --precision, --normals, --cross-tangent and "
                              "--orient are the defaults of its mesh objects, and a cache object must have been "
                              "built with those given");
  auto* cache = c->add_option("--cache", a->cache, "patch cache file");
  auto* mesh = c->add_option("--mesh", a->mesh, "mesh file (patches built lazily near the contact point)");
  c->add_option("--patch-capacity", a->patchCapacity,
                "with a mesh: patches held at once, least recently used evicted (<= 0: no bound)")
      ->check(forceOptionCheck("patch_capacity"))
      ->capture_default_str();
  scene->excludes(cache)->excludes(mesh);
  cache->excludes(mesh);
  c->add_option("--method", a->method, "patch|direct|shading (default for scene objects)")
      ->check(forceOptionCheck("method"))
      ->capture_default_str();
  c->add_option("--device", a->device,
                "haptic device: null|scripted|scripted:slide|scripted:circle|replay:FILE (CSV t,x,y,z; - reads "
                "stdin)|udp:[HOST:]PORT (network bridge: HIP packets in, FORCE packets out; HOST defaults to "
                "127.0.0.1, PORT 0 picks a free port)")
      ->capture_default_str();
  c->add_flag("--paced", a->paced,
              "device-paced: one step per received sample (udp only) instead of the fixed --rate; --rate is then "
              "the nominal sample rate that sets the deadline");
  c->add_option("--watchdog-ms", a->watchdogMs,
                "udp: no fresh sample for this long latches a stale-device fault (zero force), ms")
      ->capture_default_str();
  c->add_option("--rate", a->rate, "servo rate, Hz, 1..10000")->check(loopOptionCheck("rate"))->capture_default_str();
  c->add_option("--duration", a->duration, "seconds (> 0)")->check(loopOptionCheck("duration"))->capture_default_str();
  c->add_option("--stiffness", a->stiffness, "N/m, in (0, 1e12] (default for scene objects)")
      ->check(forceOptionCheck("stiffness"))
      ->capture_default_str();
  c->add_option("--speed", a->speed,
                "scripted device speed along its path, m/s (0 < speed <= 10: a hand's speed, with room to spare)")
      ->capture_default_str();
  auto* depth = c->add_option("--depth", a->depth,
                              "scripted depth below the surface, m (default: 1% of the bounding-box diagonal)");
  c->add_option("--record", a->record, "write per-step records to this CSV (a writer thread; the loop never blocks)");
  c->add_option("--max-force", a->safety.maxForce, "force limit, N")
      ->check(loopOptionCheck("max_force"))
      ->capture_default_str();
  c->add_option("--max-force-step", a->safety.maxForceStep, "force change limit per step, N")
      ->check(loopOptionCheck("max_force_step"))
      ->capture_default_str();
  c->add_option("--ramp", a->safety.rampTime, "force ramp-in at start, s (0: none)")
      ->check(loopOptionCheck("ramp_time"))
      ->capture_default_str();
  c->add_option("--max-missed", a->safety.maxConsecutiveMisses,
                "consecutive missed deadlines that latch a zero-force fault")
      ->check(loopOptionCheck("max_missed"))
      ->capture_default_str();
  c->add_option("--spin-us", a->spinUs, "busy-wait before each deadline, us")->capture_default_str();
  addSurfaceArgs(*c, a->patch);  // not addBackendArgs: --device is the haptic device here
  addRefineArgs(*c, a->refine);
  c->add_flag(
      "--json", a->json,
      "print the report as one JSON object on stdout (objects, device, rate_hz, duration_s, step_compute_us, "
      "wake_up_lateness_us, steps, ticks, elapsed_s, stopped, missed_deadlines, max_consecutive_misses, "
      "skipped_ticks, contact_steps, contact_onsets, patches_built, faces, safety, records, exit_status; with a "
      "udp device also udp: datagrams, accepted, superseded, duplicates, out_of_order, resyncs, foreign, "
      "wrong_version, malformed {size, magic, type, reserved, non_finite, out_of_range}, forces_sent, send_errors); "
      "the set-up lines go to stderr");
  c->add_option("--rt-priority", a->rtPriority, "SCHED_FIFO priority 1..99 and mlockall (0: off)")
      ->check(CLI::Range(0, 99))
      ->capture_default_str();
  c->callback([a, depth] {
    a->depthGiven = depth->count() > 0;
    run(*a);
  });
}

}  // namespace sf::cli
