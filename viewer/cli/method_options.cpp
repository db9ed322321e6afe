#include "viewer/cli/method_options.h"

#include "viewer/cli/commands.h"

namespace penumbra {

void addMethodOptions(CLI::App& c, MethodOptions& o, bool batchSchedule) {
  BpConfig& bp = o.bp;
  NetworkConfig& net = bp.network;
  FilterConfig& filter = bp.filter;
  c.add_option("--method", o.method,
               "Rendering method: ld (low-discrepancy sampling, box filter), bp (the BP "
               "network adaptive sampling and reconstruction), or a baseline: fdiv "
               "(f-divergence), fuzzy (fuzzy uncertainty, re-implemented), gem (greedy error "
               "minimisation with its filterbank), cycles (half-buffer error)")
      ->check(CLI::IsMember(methodNames()))
      ->capture_default_str();

  c.add_option("--preset", o.preset,
               "BP configuration: paper (ALGORITHM.md's recommendations, the defaults below) or "
               "tuned (our measured improvement: no candidate choice, no warping, plain mean, "
               "--sigma-c 0.05; an explicit --sigma-c still applies)")
      ->check(CLI::IsMember({"paper", "tuned"}))
      ->capture_default_str();

  const char* table = "BP method (paper's Table 1)";
  c.add_option("--nit", net.epochs, "Training epochs per (re)training, Nit")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str()
      ->group(table);
  c.add_option("--hidden", net.hidden, "Hidden units Nm")
      ->check(CLI::Range(1, kMaxNetHidden))
      ->capture_default_str()
      ->group(table);
  c.add_option("--inputs", net.inputs,
               "Network inputs: 4 = (radius, u, v, t) as in the paper's experiments, "
               "5 = (dx, dy, u, v, t)")
      ->check(CLI::IsMember({4, 5}))
      ->capture_default_str()
      ->group(table);
  c.add_option("--psi", bp.psi, "Bias threshold Psi: pixels above it are difficult")
      ->check(CLI::Range(0.0f, 1e6f))
      ->capture_default_str()
      ->group(table);
  c.add_option("--error-threshold", net.errorThreshold,
               "Network error threshold e: training stops below it, and pixels with er <= e "
               "count as converged")
      ->check(CLI::Range(0.0f, 1e9f))
      ->capture_default_str()
      ->group(table);
  c.add_option("--candidates", bp.candidates, "Candidates per new sample, N_candi")
      ->check(CLI::Range(1, 64))
      ->capture_default_str()
      ->group(table);
  c.add_option("--slices", bp.slicesPerSide, "Slices per pixel side S (S x S slices)")
      ->check(CLI::Range(1, kMaxSlicesPerSide))
      ->capture_default_str()
      ->group(table);
  c.add_option("--levels", bp.histogramLevels, "Histogram levels m of a slice")
      ->check(CLI::Range(1, kMaxHistogramLevels))
      ->capture_default_str()
      ->group(table);
  c.add_option("--radius", filter.radius, "Filter radius r ((2r+1)^2 window)")
      ->check(CLI::Range(0, 32))
      ->capture_default_str()
      ->group(table);
  c.add_option("--alphas", filter.alphas,
               "Spatial falloffs alpha_1..alpha_n, widest filter first (comma separated)")
      ->delimiter(',')
      ->expected(1, 16)
      ->capture_default_str()
      ->group(table);
  o.sigmaCOption =
      c.add_option("--sigma-c", filter.sigmaC, "Range falloff sigma_c on tone-mapped RGB")
          ->check(CLI::Range(1e-6f, 1e6f))
          ->capture_default_str()
          ->group(table);
  c.add_option("--phi", filter.phi,
               "Bias thresholds Phi choosing alpha (ascending, one fewer than --alphas)")
      ->delimiter(',')
      ->expected(0, 15)
      ->capture_default_str()
      ->group(table);
  c.add_option("--second-pass-alpha", filter.secondPassAlpha,
               "Index (from 0) into --alphas of the second pass's falloff (alpha_3)")
      ->check(CLI::Range(0, 15))
      ->capture_default_str()
      ->group(table);
  c.add_option("--bias-h", net.biasHidden, "Fixed hidden threshold b_h")
      ->capture_default_str()
      ->group(table);
  c.add_option("--bias-o", net.biasOutput, "Fixed output threshold b_o")
      ->capture_default_str()
      ->group(table);
  c.add_option("--learning-rate", o.learningRate,
               "Learning-rate control by er: bold (x1.05 on improvement, x0.7 on a rise) or "
               "proportional (to er / er_first)")
      ->check(CLI::IsMember({"bold", "proportional"}))
      ->capture_default_str()
      ->group(table);
  c.add_option("--mu", net.muStart, "Initial learning rate")
      ->check(CLI::Range(1e-6f, 10.0f))
      ->capture_default_str()
      ->group(table);
  c.add_option("--mu-min", net.muMin, "Smallest learning rate")
      ->check(CLI::Range(1e-6f, 10.0f))
      ->capture_default_str()
      ->group(table);
  c.add_option("--mu-max", net.muMax, "Largest learning rate")
      ->check(CLI::Range(1e-6f, 10.0f))
      ->capture_default_str()
      ->group(table);

  const char* schedule = "BP method: schedule";
  c.add_option("--coarse-spp", bp.coarseSpp,
               "Samples per pixel of the coarse pass N0 (0 = max(4, spp/4), a power of two)")
      ->check(CLI::Range(0, 1 << 20))
      ->capture_default_str()
      ->group(schedule);
  if (batchSchedule)
    c.add_option("--rounds", bp.maxRounds,
                 "Adaptive rounds that spend the rest of the budget (BP and the baselines)")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str()
        ->group(schedule);
  c.add_option("--reservoir", bp.reservoir,
               "Samples kept per pixel for training and candidate scoring (bounds memory)")
      ->check(CLI::Range(1, 1 << 16))
      ->capture_default_str()
      ->group(schedule);

  const char* baselines = "Baselines: fdiv, fuzzy, gem, cycles (ALGORITHM.md section 10)";
  c.add_option("--initial-spp", o.allocation.initialSpp,
               "Samples per pixel of the initial pass N0 (0 = min(4, spp))")
      ->check(CLI::Range(0, 1 << 20))
      ->capture_default_str()
      ->group(baselines);
  c.add_option("--batch", o.allocation.batch,
               "Samples a chosen pixel gets per round (0 = spp; 8 in the viewer)")
      ->check(CLI::Range(0, 1 << 20))
      ->capture_default_str()
      ->group(baselines);
  c.add_option("--divergence", o.divergence,
               "fdiv: hellinger (the BP paper's eq. 15), kl (Kullback-Leibler) or chi2")
      ->check(CLI::IsMember({"hellinger", "kl", "chi2"}))
      ->capture_default_str()
      ->group(baselines);
  c.add_option("--gamma", o.gamma, "gem: confidence gamma of the bias test")
      ->check(CLI::Range(1e-4f, 0.52f))
      ->capture_default_str()
      ->group(baselines);

  const char* ablation = "BP method: ablations (ALGORITHM.md section 12)";
  c.add_option("--targets", o.targets,
               "Training targets: per-sample (each sample's tone-mapped radiance) or "
               "pixel-mean (the paper's literal reading)")
      ->check(CLI::IsMember({"per-sample", "pixel-mean"}))
      ->capture_default_str()
      ->group(ablation);
  c.add_option("--prediction-draws", bp.predictionDraws,
               "Lens/time draws K averaged for the prediction I' (1 = the paper's one draw)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str()
      ->group(ablation);
  c.add_option("--candidate-mode", o.candidateMode,
               "traced: trace every candidate and keep the best (eq. 16); predicted: score "
               "candidates by the network, trace only the best, then test it for outliers")
      ->check(CLI::IsMember({"traced", "predicted"}))
      ->capture_default_str()
      ->group(ablation);
  c.add_option("--outlier-tau", bp.outlierTau,
               "Predicted mode: reject a sample whose relative distance to its slice's mean "
               "exceeds this")
      ->check(CLI::Range(1e-6f, 1e6f))
      ->capture_default_str()
      ->group(ablation);
  c.add_flag("--no-warping", o.noWarping,
             "Do not move slice B's sample into slice C: every slice gets its own")
      ->group(ablation);
  c.add_flag("--no-outlier-removal", o.noOutlierRemoval,
             "Keep the first candidate (one traced sample per slot, no eq. 16 choice, no "
             "outlier test)")
      ->group(ablation);
  c.add_flag("--no-second-pass", o.noSecondPass, "Skip the second bilateral pass (alpha_3)")
      ->group(ablation);
  c.add_flag("--plain-mean", o.plainMean,
             "Pixel estimate = plain mean of its samples instead of the mean of slice means")
      ->group(ablation);
  c.add_flag("--no-top-up", o.noTopUp,
             "Sample only difficult pixels (bias > Psi, er > e), even if budget is left over")
      ->group(ablation);
  c.add_flag("--no-reconstruct", o.noReconstruct,
             "Output the raw per-pixel estimate, without the bilateral filterbank")
      ->group(ablation);
}

BpConfig MethodOptions::bpConfig(int spp, uint64_t seed, SamplerKind sampler) const {
  BpConfig c = bp;
  c.spp = spp;
  c.seed = seed;
  c.sampler = sampler;
  c.targets = targets == "pixel-mean" ? TargetMode::PixelMean : TargetMode::PerSample;
  c.candidateMode = candidateMode == "predicted" ? CandidateMode::Predicted : CandidateMode::Traced;
  c.network.rate = learningRate == "proportional" ? LearningRateMode::Proportional
                                                  : LearningRateMode::BoldDriver;
  c.warping = !noWarping;
  c.outlierRemoval = !noOutlierRemoval;
  c.filter.secondPass = !noSecondPass;
  c.stratifiedMean = !plainMean;
  c.topUp = !noTopUp;
  c.reconstruct = !noReconstruct;
  if (preset == "tuned") {
    const float sigmaC = c.filter.sigmaC;
    applyBpPreset(c, BpPreset::Tuned);
    if (sigmaCOption && sigmaCOption->count() > 0) c.filter.sigmaC = sigmaC;
  }
  const std::string problem = c.validate();
  if (!problem.empty()) throw CommandError(problem);
  return c;
}

MethodSpec MethodOptions::spec(int spp, uint64_t seed, SamplerKind sampler) const {
  MethodSpec s;
  const auto kind = parseMethodKind(method);
  if (!kind) throw CommandError("--method: unknown method '" + method + "'");
  s.kind = *kind;
  s.seed = seed;
  s.spp = spp;
  s.sampler = sampler;
  if (s.kind == MethodKind::Bp) s.bp = bpConfig(spp, seed, sampler);
  s.allocation = allocation;
  s.allocation.rounds = bp.maxRounds;
  s.divergence = divergence == "kl"     ? Divergence::KullbackLeibler
                 : divergence == "chi2" ? Divergence::ChiSquare
                                        : Divergence::Hellinger;
  s.gamma = gamma;
  const std::string problem = validate(s);
  if (!problem.empty()) throw CommandError(problem);
  return s;
}

}  // namespace penumbra
