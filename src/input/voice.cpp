#include "input/voice.h"

#include <algorithm>
#include <cmath>

namespace mar {

const char* viseme_name(Viseme v) {
  switch (v) {
    case Viseme::Closed: return "closed";
    case Viseme::A: return "a";
    case Viseme::I: return "i";
    case Viseme::U: return "u";
    case Viseme::E: return "e";
    case Viseme::O: return "o";
  }
  return "?";
}

namespace {
constexpr int kOrder = 12;      // LPC order at about 11 kHz (2 + fs / 1000)
constexpr int kBins = 256;      // the envelope from 0 to 4 kHz
constexpr double kTop = 4000;
}  // namespace

VoiceAnalyzer::VoiceAnalyzer(int sample_rate, const VoiceOptions& o) : o_(o), rate_(std::max(1000, sample_rate)) {
  frame_n_ = std::max(16, int(std::lround(o_.frame_s * rate_)));
  hop_n_ = std::max(1, int(std::lround(o_.hop_s * rate_)));
  decim_ = std::max(1, int(std::lround(rate_ / 11025.0)));
  ring_.assign(size_t(frame_n_), 0.0);
  frame_.assign(size_t(frame_n_), 0.0);
  dec_.assign(size_t(frame_n_ / decim_ + 1), 0.0);
  env_.assign(kBins, 0.0);
}

void VoiceAnalyzer::calibrate(Viseme v, double f1, double f2) {
  if (v == Viseme::Closed || !(f1 > 0) || !(f2 > 0)) return;
  o_.templates[size_t(v) - 1] = {f1, f2};
}

Viseme VoiceAnalyzer::nearest(double f1, double f2) const {
  Viseme best = Viseme::A;
  double bd = 1e300;
  for (size_t k = 0; k < 5; ++k) {
    const double d1 = std::log(f1 / o_.templates[k][0]), d2 = std::log(f2 / o_.templates[k][1]);
    const double d = d1 * d1 + 0.6 * d2 * d2;
    if (d < bd) {
      bd = d;
      best = Viseme(k + 1);
    }
  }
  return best;
}

bool VoiceAnalyzer::formants(double& f1, double& f2) {
  // Decimate to about 11 kHz (averaging: a crude low-pass, enough below 4 kHz), pre-emphasis,
  // Hann window, autocorrelation, Levinson-Durbin, then the envelope's peaks.
  const int n = frame_n_ / decim_;
  for (int i = 0; i < n; ++i) {
    double s = 0;
    for (int k = 0; k < decim_; ++k) s += frame_[size_t(i * decim_ + k)];
    dec_[size_t(i)] = s / decim_;
  }
  for (int i = n - 1; i > 0; --i) dec_[size_t(i)] -= 0.97 * dec_[size_t(i - 1)];
  for (int i = 0; i < n; ++i) dec_[size_t(i)] *= 0.5 - 0.5 * std::cos(2 * M_PI * i / (n - 1));
  double r[kOrder + 1];
  for (int l = 0; l <= kOrder; ++l) {
    double s = 0;
    for (int i = l; i < n; ++i) s += dec_[size_t(i)] * dec_[size_t(i - l)];
    r[l] = s;
  }
  if (!(r[0] > 1e-12)) return false;
  r[0] *= 1.0001;  // a little white noise: a stable predictor
  double a[kOrder + 1] = {1}, tmp[kOrder + 1];
  double err = r[0];
  for (int i = 1; i <= kOrder; ++i) {
    double acc = r[i];
    for (int j = 1; j < i; ++j) acc -= a[j] * r[i - j];
    const double k = acc / err;
    std::copy(a, a + kOrder + 1, tmp);
    a[i] = k;
    for (int j = 1; j < i; ++j) a[j] = tmp[j] - k * tmp[i - j];
    err *= 1 - k * k;
    if (!(err > 0)) return false;
  }
  const double fs = double(rate_) / decim_;
  for (int b = 0; b < kBins; ++b) {
    const double w = 2 * M_PI * (kTop * b / kBins) / fs;
    double re = 1, im = 0;
    for (int j = 1; j <= kOrder; ++j) {
      re -= a[j] * std::cos(j * w);
      im += a[j] * std::sin(j * w);
    }
    env_[size_t(b)] = 1 / (re * re + im * im);
  }
  f1 = f2 = 0;
  for (int b = 1; b + 1 < kBins; ++b) {
    if (!(env_[size_t(b)] > env_[size_t(b - 1)] && env_[size_t(b)] >= env_[size_t(b + 1)])) continue;
    // the peak, interpolated (a parabola through three bins)
    const double y0 = std::log(env_[size_t(b - 1)]), y1 = std::log(env_[size_t(b)]), y2 = std::log(env_[size_t(b + 1)]);
    const double den = y0 - 2 * y1 + y2, off = den != 0 ? 0.5 * (y0 - y2) / den : 0;
    const double f = kTop * (b + std::clamp(off, -0.5, 0.5)) / kBins;
    if (f1 == 0) {
      if (f >= 180 && f <= 1100) f1 = f;
    } else if (f >= f1 + 150 && f <= 3200) {
      f2 = f;
      break;
    }
  }
  return f1 > 0 && f2 > 0;
}

VoiceFrame VoiceAnalyzer::analyse() {
  // The frame: the last frame_n_ samples, oldest first.
  // The level from its last 10 ms (quick to rise at an onset), the vowel from all 25.
  const size_t start = write_ + ring_.size() - size_t(frame_n_);  // (the ring starts as silence)
  const int recent = std::min(frame_n_, std::max(1, int(std::lround(0.010 * rate_))));
  double sum = 0;
  for (int i = 0; i < frame_n_; ++i) {
    const double s = ring_[(start + size_t(i)) % ring_.size()];
    frame_[size_t(i)] = s;
    if (i >= frame_n_ - recent) sum += s * s;
  }
  const double rms = std::sqrt(sum / recent);
  const double db = std::max(-90.0, 20 * std::log10(std::max(rms, 1e-6)));  // (a floor: a rise from silence is quick)
  const double tau = db > level_ ? o_.attack_s : o_.release_s;
  level_ = tau <= 0 ? db : level_ + (db - level_) * (1 - std::exp(-o_.hop_s / tau));
  VoiceFrame f;
  f.t = double(write_) / rate_;
  f.level_db = level_;
  const bool open = level_ >= o_.gate_db;
  f.onset = open && !open_;
  open_ = open;
  if (!open) {
    shown_ = candidate_ = Viseme::Closed;
    candidate_frames_ = 0;
    f.viseme = Viseme::Closed;
    return f;
  }
  double f1 = 0, f2 = 0;
  if (formants(f1, f2)) {
    f.f1 = f1;
    f.f2 = f2;
    const Viseme v = nearest(f1, f2);
    if (shown_ == Viseme::Closed) {
      shown_ = v;  // a mouth opening takes the first vowel at once
    } else if (v != shown_) {
      candidate_frames_ = v == candidate_ ? candidate_frames_ + 1 : 1;
      candidate_ = v;
      if (candidate_frames_ >= 2) shown_ = v;
    } else {
      candidate_frames_ = 0;
    }
  } else if (shown_ == Viseme::Closed) {
    shown_ = Viseme::A;  // voiced but no formants heard: open
  }
  f.viseme = shown_;
  return f;
}

bool VoiceAnalyzer::measure_vowel(int sample_rate, std::span<const int16_t> pcm, double& f1, double& f2, const VoiceOptions& o) {
  VoiceAnalyzer v(sample_rate, o);
  std::vector<double> a, b;
  v.push(pcm, [&](const VoiceFrame& f) {
    if (f.viseme != Viseme::Closed && f.f1 > 0 && f.f2 > 0) {
      a.push_back(f.f1);
      b.push_back(f.f2);
    }
  });
  if (a.size() < 3) return false;
  std::nth_element(a.begin(), a.begin() + long(a.size() / 2), a.end());
  std::nth_element(b.begin(), b.begin() + long(b.size() / 2), b.end());
  f1 = a[a.size() / 2];
  f2 = b[b.size() / 2];
  return true;
}

}  // namespace mar
