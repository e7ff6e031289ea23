#include "synth/footage_draw.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hoof::synth {
namespace {

constexpr int kLutSize = 16384;
/// Shadows drawn per exposure at most (the shadow moves far less than the ball).
constexpr int kShadowSamples = 8;

cv::Rect Union(const cv::Rect& a, const cv::Rect& b) {
  if (a.area() <= 0) return b;
  if (b.area() <= 0) return a;
  return a | b;
}

cv::Vec3f Bgr(const Eigen::Vector3d& rgb) {
  return {static_cast<float>(rgb.z()), static_cast<float>(rgb.y()), static_cast<float>(rgb.x())};
}

/// Dark paint on the ball at body-frame normal q: 1 on a line, 0 off it, over a soft edge of
/// `edge` (about one pixel on the ball).
double Paint(BallTexture texture, const Eigen::Vector3d& q, double edge) {
  const auto line = [edge](double d, double half) {
    return std::clamp((half - std::abs(d)) / edge + 0.5, 0.0, 1.0);
  };
  switch (texture) {
    case BallTexture::kPlain:
      return 0.0;
    case BallTexture::kStripes:
      return std::max(line(q.x(), 0.09), line(q.y(), 0.09));
    case BallTexture::kCross:
      return q.z() > 0.2 ? std::max(line(q.x(), 0.07), line(q.y(), 0.07)) : 0.0;
  }
  return 0.0;
}

}  // namespace

/// Everything drawn at one sub-frame time.
struct FootageFrameRenderer::Sample {
  double t_s = 0.0;
  BallState ball;
  SphereImage image;
  Eigen::Vector3d c_cam = Eigen::Vector3d::Zero();  ///< Ball centre in camera coordinates.
  cv::Rect ball_rect, shadow_rect;
  HandShape hand;
  double hand_light = 0.0;
};

double LinearToSrgbLevel(double v) {
  v = std::clamp(v, 0.0, 1.0);
  const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
  return 255.0 * s;
}

FootageFrameRenderer::FootageFrameRenderer(const FootagePlan& plan, int jobs)
    : plan_(plan),
      spec_(plan.spec),
      camera_(plan.camera),
      path_(plan.path),
      hand_(plan.hand),
      schedule_(plan.schedule),
      light_(plan.light) {
  const FootageSpec& spec = spec_;
  const PinholeCamera& camera = camera_;
  room_ = RenderRoom(spec, camera, light_, jobs);
  srgb_lut_.resize(kLutSize + 1);
  for (int i = 0; i <= kLutSize; ++i)
    srgb_lut_[static_cast<std::size_t>(i)] =
        static_cast<float>(LinearToSrgbLevel(1.0 * i / kLutSize));
  const int w = camera.width_px(), h = camera.height_px();
  gain_.create(h, w, CV_32FC3);
  const Eigen::Vector2d c = camera.principal_point_px();
  const double r2 = 0.25 * (w * w + h * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double d2 = (x - c.x()) * (x - c.x()) + (y - c.y()) * (y - c.y());
      const auto g = static_cast<float>(1 - spec.sensor.vignetting * std::min(1.0, d2 / r2));
      gain_.at<cv::Vec3f>(y, x) = {g, g, g};
    }
  room_srgb_.create(h, w, CV_32FC3);
  ToSrgb(room_.linear, cv::Rect(0, 0, w, h), room_srgb_);
  albedo_bgr_ = BallAlbedoRgb(spec.ball.color);
}

void FootageFrameRenderer::ToSrgb(const cv::Mat& linear, const cv::Rect& roi, cv::Mat& srgb) const {
  for (int y = 0; y < roi.height; ++y) {
    const auto* in = linear.ptr<cv::Vec3f>(y);
    const auto* g = gain_.ptr<cv::Vec3f>(y + roi.y) + roi.x;
    auto* out = srgb.ptr<cv::Vec3f>(y + roi.y) + roi.x;
    for (int x = 0; x < roi.width; ++x)
      for (int ch = 0; ch < 3; ++ch) {
        const float v = std::clamp(in[x][ch] * g[x][ch], 0.0f, 1.0f) * kLutSize;
        const int i = std::min(kLutSize - 1, static_cast<int>(v));
        const float f = v - static_cast<float>(i);  // linear between entries
        out[x][ch] = srgb_lut_[static_cast<std::size_t>(i)] * (1 - f) +
                     srgb_lut_[static_cast<std::size_t>(i + 1)] * f;
      }
  }
}

FootageFrameRenderer::Sample FootageFrameRenderer::MakeSample(double t) const {
  Sample s;
  s.t_s = t;
  if (path_.present) {
    s.ball = path_.At(t);
    s.image = camera_.ImageOfSphere(s.ball.p_WC_m, path_.radius_m);
    s.c_cam = camera_.ToCamera(s.ball.p_WC_m);
  }
  if (hand_.present()) {
    s.hand = hand_.ShapeAt(t);
    const Eigen::Vector3d n = Eigen::Vector3d(0, 0.6, 0.8);
    s.hand_light = light_.Ambient() + light_.Direct(s.hand.p_W_m, n);
  }
  s.ball_rect = s.shadow_rect = cv::Rect();
  if (s.image.valid) {
    const double a = s.image.semi_major_px, b = s.image.semi_minor_px;
    const double th = s.image.major_angle_rad;
    const double hx = std::hypot(a * std::cos(th), b * std::sin(th));
    const double hy = std::hypot(a * std::sin(th), b * std::cos(th));
    const Eigen::Vector2d& c = s.image.center_px;
    s.ball_rect = cv::Rect(cv::Point(static_cast<int>(std::floor(c.x() - hx)) - 2,
                                     static_cast<int>(std::floor(c.y() - hy)) - 2),
                           cv::Point(static_cast<int>(std::ceil(c.x() + hx)) + 3,
                                     static_cast<int>(std::ceil(c.y() + hy)) + 3));
  }
  const Eigen::Vector3d& L = light_.p_W();
  const Eigen::Vector3d& C = s.ball.p_WC_m;
  if (path_.present && C.y() < L.y()) {
    const Eigen::Vector3d S = L + (C - L) * (L.y() / (L.y() - C.y()));  // on y = 0
    const double lc = (L - C).norm();
    const double rs =
        path_.radius_m * (L - S).norm() / lc + light_.radius_m() * (C - S).norm() / lc;
    const double rho = 1.3 * rs / std::max(0.05, (L - S).normalized().y()) + 0.005;
    double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
    bool ok = true;
    for (int i = 0; i < 16 && ok; ++i) {
      const double phi = i * 2 * std::numbers::pi / 16;
      const Eigen::Vector3d p = S + rho * Eigen::Vector3d(std::cos(phi), 0, std::sin(phi));
      const Eigen::Vector2d u = camera_.Project(p);
      ok = u.allFinite();
      x0 = std::min(x0, u.x()), y0 = std::min(y0, u.y());
      x1 = std::max(x1, u.x()), y1 = std::max(y1, u.y());
    }
    if (ok && x1 - x0 < 1e5 && y1 - y0 < 1e5)
      s.shadow_rect = cv::Rect(
          cv::Point(static_cast<int>(std::floor(x0)) - 1, static_cast<int>(std::floor(y0)) - 1),
          cv::Point(static_cast<int>(std::ceil(x1)) + 2, static_cast<int>(std::ceil(y1)) + 2));
  }
  return s;
}

cv::Rect FootageFrameRenderer::SampleBounds(const Sample& s) const {
  cv::Rect r = Union(s.ball_rect, s.shadow_rect);
  if (s.hand.present) r = Union(r, s.hand.bounds);
  return r & cv::Rect(0, 0, camera_.width_px(), camera_.height_px());
}

cv::Vec3f FootageFrameRenderer::BallColour(const Sample& s, double x, double y) const {
  const double r = path_.radius_m;
  const Eigen::Vector3d d = camera_.RayC(x, y), &c = s.c_cam;
  const double b = d.dot(c), dd = d.squaredNorm();
  const double disc = std::max(0.0, b * b - dd * (c.squaredNorm() - r * r));
  const Eigen::Vector3d X = d * ((b - std::sqrt(disc)) / dd);
  const Eigen::Matrix3d R_WC = camera_.R_CW().transpose();
  const Eigen::Vector3d n = (R_WC * (X - c)).normalized();
  const Eigen::Vector3d X_W = camera_.p_W_m() + R_WC * X;
  const Eigen::Vector3d q = s.ball.R_WB.transpose() * n;
  const double edge = 1.0 / std::max(1.0, s.image.radius_px);
  const double paint = Paint(spec_.ball.texture, q, edge);
  const Eigen::Vector3d albedo =
      albedo_bgr_ * (1 - paint) + Eigen::Vector3d::Constant(0.03) * paint;
  const double lit = light_.Ambient(0.65 + 0.35 * n.y()) + light_.Direct(X_W, n);
  Eigen::Vector3d rgb = albedo * lit;
  const Eigen::Vector3d l = (light_.p_W() - X_W).normalized();
  const Eigen::Vector3d v = (camera_.p_W_m() - X_W).normalized();
  if (n.dot(l) > 0 && spec_.ball.specular > 0) {
    const double nh = std::max(0.0, n.dot((l + v).normalized()));
    rgb += Eigen::Vector3d::Constant(spec_.ball.specular * std::pow(nh, spec_.ball.shininess) *
                                     light_.Direct(X_W, l));
  }
  return Bgr(rgb);
}

void FootageFrameRenderer::DrawBall(const Sample& s, const cv::Rect& roi, bool sharp,
                                    cv::Mat& linear) const {
  if (!s.image.valid) return;
  const cv::Rect box = s.ball_rect & roi;
  const Eigen::Matrix3d& Q = s.image.conic;
  const auto value = [&Q](double x, double y) {
    const Eigen::Vector3d u{x, y, 1};
    return u.dot(Q * u);
  };
  for (int y = box.y; y < box.y + box.height; ++y) {
    auto* row = linear.ptr<cv::Vec3f>(y - roi.y) - roi.x;
    for (int x = box.x; x < box.x + box.width; ++x) {
      const Eigen::Vector2d g =
          2 * (Q.topLeftCorner<2, 2>() * Eigen::Vector2d(x, y) + Q.block<2, 1>(0, 2));
      const double inside = value(x, y) / std::max(1e-300, g.norm());  // px, > 0 inside
      if (inside <= -0.75) continue;
      if (inside >= 0.75) {
        row[x] = BallColour(s, x, y);
        continue;
      }
      if (!sharp) {  // blurred: the time samples smooth the rim; coverage from the distance
        const auto a = static_cast<float>(std::clamp(0.5 + inside, 0.0, 1.0));
        row[x] = row[x] * (1 - a) + BallColour(s, x, y) * a;
        continue;
      }
      cv::Vec3f sum(0, 0, 0);
      int hits = 0;
      for (int i = 0; i < 16; ++i) {  // the rim: 4 x 4 rays
        const double sx = x - 0.375 + 0.25 * (i & 3), sy = y - 0.375 + 0.25 * (i >> 2);
        if (value(sx, sy) < 0) continue;
        sum += BallColour(s, sx, sy);
        ++hits;
      }
      const float a = static_cast<float>(hits) / 16.0f;
      if (hits > 0) row[x] = row[x] * (1 - a) + sum * (1.0f / 16);
    }
  }
}

void FootageFrameRenderer::DrawShadow(const Sample& s, const cv::Rect& roi, cv::Mat& linear) const {
  const cv::Rect box = s.shadow_rect & roi;
  const Eigen::Vector3d o = camera_.p_W_m();
  for (int y = box.y; y < box.y + box.height; ++y) {
    auto* row = linear.ptr<cv::Vec3f>(y - roi.y) - roi.x;
    const auto* direct = room_.direct.ptr<cv::Vec3f>(y);
    for (int x = box.x; x < box.x + box.width; ++x) {
      if (direct[x][0] == 0 && direct[x][1] == 0 && direct[x][2] == 0) continue;
      const Eigen::Vector3d d = camera_.RayW(x, y);
      if (d.y() >= 0) continue;
      const Eigen::Vector3d p = o + d * (-o.y() / d.y());
      const double f =
          ShadowFraction(p, light_.p_W(), light_.radius_m(), s.ball.p_WC_m, path_.radius_m);
      row[x] -= direct[x] * static_cast<float>(f);
    }
  }
}

void FootageFrameRenderer::DrawHand(const Sample& s, const cv::Rect& roi, cv::Mat& linear) const {
  if (!s.hand.present) return;
  const cv::Rect box = s.hand.bounds & roi;
  const cv::Vec3f skin = Bgr(hand_.skin_rgb() * s.hand_light);
  for (int y = box.y; y < box.y + box.height; ++y) {
    auto* row = linear.ptr<cv::Vec3f>(y - roi.y) - roi.x;
    for (int x = box.x; x < box.x + box.width; ++x) {
      double rim = 0;
      const double d = s.hand.Distance(x, y, &rim);
      const double a = std::clamp(0.5 - d, 0.0, 1.0);
      if (a == 0) continue;
      const double shade = 0.55 + 0.45 * std::sqrt(std::max(0.0, 1 - (1 - rim) * (1 - rim)));
      row[x] = row[x] * static_cast<float>(1 - a) + skin * static_cast<float>(a * shade);
    }
  }
}

void FootageFrameRenderer::AddNoise(int capture, cv::Mat& srgb) const {
  const SensorOptions& o = spec_.sensor;
  if (!o.noise || (o.read_noise == 0 && o.shot_noise == 0)) return;
  cv::RNG rng(spec_.seed * 0x94D049BB133111EBull +
              static_cast<std::uint64_t>(capture) * 2654435761u + 7);
  thread_local cv::Mat n, sigma;
  n.create(srgb.size(), CV_32FC3);
  rng.fill(n, cv::RNG::NORMAL, 0.0, 1.0);
  srgb.convertTo(sigma, CV_32FC3, o.shot_noise, o.read_noise * o.read_noise);
  cv::sqrt(cv::max(sigma, 0.0), sigma);
  srgb += n.mul(sigma);
}

cv::Mat FootageFrameRenderer::Render(int capture) const {
  const double t = schedule_.capture_times_s[static_cast<std::size_t>(capture)];
  const int n = ExposureSamples(plan_, capture);
  const double T = spec_.sensor.motion_blur ? schedule_.exposure_s : 0.0;
  std::vector<Sample> samples;
  cv::Rect roi;
  for (int i = 0; i < n; ++i) {
    samples.push_back(MakeSample(t + T * ((i + 0.5) / n - 0.5)));
    roi = Union(roi, SampleBounds(samples.back()));
  }
  thread_local cv::Mat srgb, sum, shadowed, patch;  // reused: no page faults per frame
  room_srgb_.copyTo(srgb);
  if (roi.area() > 0) {
    sum.create(roi.size(), CV_32FC3);
    sum.setTo(cv::Scalar::all(0));
    // The shadow moves slowly: drawn once for each group of up to `group` samples, at its
    // middle. Each sample adds the shadowed room, and its ball and hand where they are.
    const int group = (n + kShadowSamples - 1) / kShadowSamples;
    for (int i = 0; i < n; ++i) {
      if (i % group == 0) {
        room_.linear(roi).copyTo(shadowed);
        DrawShadow(samples[static_cast<std::size_t>(std::min(n - 1, i + group / 2))], roi,
                   shadowed);
      }
      sum += shadowed;
      const Sample& s = samples[static_cast<std::size_t>(i)];
      const cv::Rect where = Union(s.ball_rect, s.hand.present ? s.hand.bounds : cv::Rect()) & roi;
      if (where.area() <= 0) continue;
      const cv::Rect local = where - roi.tl();
      shadowed(local).copyTo(patch);
      DrawBall(s, where, n <= 2, patch);
      DrawHand(s, where, patch);
      cv::Mat into = sum(local);
      into += patch;
      into -= shadowed(local);
    }
    sum *= 1.0 / n;
    ToSrgb(sum, roi, srgb);
  }
  AddNoise(capture, srgb);
  cv::Mat out;
  srgb.convertTo(out, CV_8UC3);
  return out;
}

}  // namespace hoof::synth
