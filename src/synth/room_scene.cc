#include "synth/room_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/parallel.h"
#include "synth/room_texture.h"

namespace hoof::synth {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kCeiling_m = 2.6;
constexpr double kRightWall_m = 2.2;

enum class Mat { kBackWall, kSideWall, kFloor, kCeiling, kPlain, kRuler, kPicture, kTableTop };

/// An axis-aligned box.
struct Box {
  Eigen::Vector3d lo, hi;
  Mat mat = Mat::kPlain;
  Eigen::Vector3d albedo{0.5, 0.5, 0.5};
};
/// A vertical cylinder standing on y0.
struct Cylinder {
  double x = 0, z = 0, y0 = 0, y1 = 0, radius = 0;
  Eigen::Vector3d albedo{0.5, 0.5, 0.5};
};

struct Hit {
  double t = kInf;
  Eigen::Vector3d p = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero();
  Mat mat = Mat::kPlain;
  Eigen::Vector3d albedo{0.5, 0.5, 0.5};
  const Box* box = nullptr;
};

/// The room's geometry and paints.
struct Room {
  const FootageSpec* spec = nullptr;
  RoomPalette palette;
  std::uint64_t seed = 0;
  double floor_y = 0, wall_z = 0, left_x = -kInf, right_x = kInf;
  std::vector<Box> boxes;
  std::vector<Cylinder> cylinders;
  std::vector<cv::Rect> box_rects, cylinder_rects;  ///< Where each may appear in the image.
  std::vector<const Box*> shelves;                  ///< Boards that shade the wall below.
};

double Uniform(const Room& room, int a, int b, double lo, double hi) {
  return lo + (hi - lo) * Hash01(a, b, room.seed + 0xC1u);
}

Eigen::Vector3d BookColour(const Room& room, int a) {
  static const Eigen::Vector3d colours[] = {
      {0.35, 0.04, 0.04}, {0.04, 0.07, 0.25}, {0.05, 0.25, 0.10}, {0.60, 0.45, 0.10},
      {0.75, 0.74, 0.70}, {0.03, 0.03, 0.03}, {0.70, 0.25, 0.04}, {0.04, 0.35, 0.35}};
  const auto i = static_cast<std::size_t>(Uniform(room, a, 1, 0, 7.999));
  return colours[i] * Uniform(room, a, 2, 0.75, 1.1);
}

/// A row of books on the board whose top is at y, from x0 to x1, then a tin and a box.
void FillShelf(Room& room, double y, double x0, double x1, int level) {
  const double z0 = room.wall_z;
  double x = x0 + 0.02;
  for (int i = 0; x < x0 + 0.55 * (x1 - x0); ++i) {
    const int id = level * 100 + i;
    const double w = Uniform(room, id, 3, 0.018, 0.045), h = Uniform(room, id, 4, 0.13, 0.21);
    const double d = Uniform(room, id, 5, 0.13, 0.19);
    room.boxes.push_back({{x, y, z0}, {x + w, y + h, z0 + d}, Mat::kPlain, BookColour(room, id)});
    x += w + (Uniform(room, id, 6, 0, 1) < 0.2 ? 0.01 : 0.001);
  }
  const double tin_x = x + 0.07;
  room.cylinders.push_back({tin_x, z0 + 0.09, y, y + 0.10, 0.035,
                            Eigen::Vector3d{0.55, 0.55, 0.52} * Uniform(room, level, 7, 0.6, 1)});
  const double bx = tin_x + 0.06;
  if (bx + 0.1 < x1)
    room.boxes.push_back({{bx, y, z0 + 0.02},
                          {bx + 0.10, y + 0.07, z0 + 0.14},
                          Mat::kPlain,
                          BookColour(room, level * 100 + 99)});
}

void AddClutter(Room& room) {
  const RoomOptions& o = room.spec->room;
  const double f = room.floor_y, w = room.wall_z;
  room.left_x = o.side_wall_x_m;
  room.right_x = kRightWall_m;
  room.boxes.push_back({{room.left_x, f, w},
                        {room.right_x, f + 0.07, w + 0.012},
                        Mat::kPlain,
                        Eigen::Vector3d::Constant(0.80)});
  const Eigen::Vector3d board = Uniform(room, 1, 9, 0, 1) < 0.5
                                    ? Eigen::Vector3d(Eigen::Vector3d::Constant(0.78))
                                    : Eigen::Vector3d(room.palette.wood * 1.2);
  for (int level = 0; level < 2; ++level) {
    const double y = 0.25 + 0.30 * level, x0 = 0.30, x1 = 1.10;
    room.boxes.push_back({{x0, y - 0.018, w}, {x1, y, w + 0.22}, Mat::kPlain, board});
    FillShelf(room, y, x0, x1, level);
  }
  room.boxes.push_back(
      {{-0.65, 0.28, w}, {-0.25, 0.56, w + 0.015}, Mat::kPicture, {0.1, 0.1, 0.1}});
  room.cylinders.push_back(
      {o.side_wall_x_m + 0.25, w + 0.22, f, f + 0.24, 0.11, {0.42, 0.17, 0.08}});
  room.boxes.push_back(
      {{0.55, f, w + 0.05}, {0.85, f + 0.20, w + 0.33}, Mat::kPlain, {0.46, 0.33, 0.19}});
  room.boxes.push_back({{-0.45, 0, -0.30}, {-0.15, 0.002, -0.27}, Mat::kRuler, {0.8, 0.6, 0.06}});
}

void AddTable(Room& room) {
  const RoomOptions& o = room.spec->room;
  const double hw = o.table_half_width_m, front = o.table_front_z_m, back = room.wall_z;
  room.boxes.push_back({{-hw, -0.035, back}, {hw, 0, front}, Mat::kTableTop, room.palette.wood});
  const Eigen::Vector3d leg = room.palette.wood * 0.7;
  for (double x : {-hw + 0.03, hw - 0.08})
    for (double z : {back + 0.03, front - 0.08})
      room.boxes.push_back({{x, room.floor_y, z}, {x + 0.05, -0.035, z + 0.05}, Mat::kPlain, leg});
}

cv::Rect ImageRect(const PinholeCamera& camera, const Eigen::Vector3d& lo,
                   const Eigen::Vector3d& hi) {
  const cv::Rect all(0, 0, camera.width_px(), camera.height_px());
  double x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d p{i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(),
                            i & 4 ? hi.z() : lo.z()};
    if (camera.ToCamera(p).z() < 0.01) return all;
    const Eigen::Vector2d u = camera.Project(p);
    x0 = std::min(x0, u.x());
    y0 = std::min(y0, u.y());
    x1 = std::max(x1, u.x());
    y1 = std::max(y1, u.y());
  }
  const cv::Rect r(static_cast<int>(std::floor(x0)) - 2, static_cast<int>(std::floor(y0)) - 2,
                   static_cast<int>(x1 - x0) + 6, static_cast<int>(y1 - y0) + 6);
  return r & all;
}

Room BuildRoom(const FootageSpec& spec, const PinholeCamera& camera) {
  Room room;
  room.spec = &spec;
  room.seed = spec.seed * 0x2545F4914F6CDD1Dull + 0x500;
  room.palette = DrawPalette(room.seed);
  room.wall_z = spec.room.wall_z_m;
  const bool table = spec.room.surface == ContactSurface::kTable;
  room.floor_y = table ? -spec.room.table_height_m : 0.0;
  if (table) AddTable(room);
  if (spec.room.clutter) AddClutter(room);
  for (const Box& b : room.boxes) {
    room.box_rects.push_back(ImageRect(camera, b.lo, b.hi));
    if (b.mat == Mat::kPlain && b.lo.z() == room.wall_z && b.hi.y() - b.lo.y() < 0.03)
      room.shelves.push_back(&b);
  }
  for (const Cylinder& c : room.cylinders)
    room.cylinder_rects.push_back(ImageRect(camera, {c.x - c.radius, c.y0, c.z - c.radius},
                                            {c.x + c.radius, c.y1, c.z + c.radius}));
  return room;
}

/// Nearest of the room's walls, floor and ceiling (the inside of a box).
Hit HitShell(const Room& room, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  Hit h;
  const auto take = [&](double t, const Eigen::Vector3d& n, Mat mat) {
    if (t > 0 && t < h.t) {
      h.t = t;
      h.n = n;
      h.mat = mat;
    }
  };
  if (d.y() < 0) take((room.floor_y - o.y()) / d.y(), {0, 1, 0}, Mat::kFloor);
  if (d.y() > 0) take((kCeiling_m - o.y()) / d.y(), {0, -1, 0}, Mat::kCeiling);
  if (d.z() < 0) take((room.wall_z - o.z()) / d.z(), {0, 0, 1}, Mat::kBackWall);
  if (d.x() < 0 && std::isfinite(room.left_x))
    take((room.left_x - o.x()) / d.x(), {1, 0, 0}, Mat::kSideWall);
  if (d.x() > 0 && std::isfinite(room.right_x))
    take((room.right_x - o.x()) / d.x(), {-1, 0, 0}, Mat::kSideWall);
  h.p = o + h.t * d;
  return h;
}

void HitBox(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d, Hit& h) {
  double t0 = -kInf, t1 = kInf;
  int axis = -1;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0) {
      if (o[i] < b.lo[i] || o[i] > b.hi[i]) return;
      continue;
    }
    double a = (b.lo[i] - o[i]) / d[i], c = (b.hi[i] - o[i]) / d[i];
    if (a > c) std::swap(a, c);
    if (a > t0) {
      t0 = a;
      axis = i;
    }
    t1 = std::min(t1, c);
  }
  if (axis < 0 || t0 > t1 || t0 <= 0 || t0 >= h.t) return;
  h.t = t0;
  h.p = o + t0 * d;
  h.n = Eigen::Vector3d::Zero();
  h.n[axis] = d[axis] > 0 ? -1 : 1;
  h.mat = b.mat;
  h.albedo = b.albedo;
  h.box = &b;
}

void HitCylinder(const Cylinder& c, const Eigen::Vector3d& o, const Eigen::Vector3d& d, Hit& h) {
  const double ox = o.x() - c.x, oz = o.z() - c.z;
  const double a = d.x() * d.x() + d.z() * d.z(), b = ox * d.x() + oz * d.z();
  const double disc = b * b - a * (ox * ox + oz * oz - c.radius * c.radius);
  if (a > 0 && disc >= 0) {
    const double t = (-b - std::sqrt(disc)) / a;
    const double y = o.y() + t * d.y();
    if (t > 0 && t < h.t && y >= c.y0 && y <= c.y1) {
      h.t = t;
      h.p = o + t * d;
      h.n = Eigen::Vector3d(h.p.x() - c.x, 0, h.p.z() - c.z) / c.radius;
      h.mat = Mat::kPlain;
      h.albedo = c.albedo;
      h.box = nullptr;
      return;
    }
  }
  if (d.y() < 0) {  // the top
    const double t = (c.y1 - o.y()) / d.y();
    const Eigen::Vector3d p = o + t * d;
    if (t > 0 && t < h.t && std::hypot(p.x() - c.x, p.z() - c.z) <= c.radius) {
      h.t = t;
      h.p = p;
      h.n = {0, 1, 0};
      h.mat = Mat::kPlain;
      h.albedo = c.albedo * 0.8;
      h.box = nullptr;
    }
  }
}

Eigen::Vector3d PictureFace(const Box& b, const Eigen::Vector3d& p, std::uint64_t seed) {
  const double u = (p.x() - b.lo.x()) / (b.hi.x() - b.lo.x());
  const double v = (p.y() - b.lo.y()) / (b.hi.y() - b.lo.y());
  if (u < 0.06 || u > 0.94 || v < 0.08 || v > 0.92) return {0.05, 0.04, 0.03};
  const int cu = static_cast<int>(u * 5), cv = static_cast<int>(v * 3);
  const double hue = Hash01(cu, cv, seed);
  return Eigen::Vector3d{0.2 + 0.6 * hue, 0.3 + 0.4 * (1 - hue),
                         0.25 + 0.5 * Hash01(cv, cu, seed)} *
         (0.6 + 0.4 * Fractal(u * 8, v * 8, 2, seed));
}

/// The hit's reflectance.
Eigen::Vector3d Albedo(const Room& room, const Hit& h) {
  const Eigen::Vector3d& p = h.p;
  const RoomPalette& pal = room.palette;
  switch (h.mat) {
    case Mat::kBackWall:
      return WallPaint(pal.wall_low, pal.wall_high, p.x(), p.y() - room.floor_y, room.seed);
    case Mat::kSideWall:
      return WallPaint(pal.side_wall, pal.side_wall * 1.05, p.z(), p.y() - room.floor_y,
                       room.seed + 1);
    case Mat::kFloor:
      if (room.spec->room.clutter) return WoodPlanks(pal, p.x(), p.z(), room.seed + 2);
      return pal.plain_floor * (1 + 0.03 * (ValueNoise(p.x() * 40, p.z() * 40, room.seed) - 0.5));
    case Mat::kCeiling:
      return Eigen::Vector3d::Constant(0.8);
    case Mat::kRuler:
      if (h.n.y() < 0.5) return h.albedo * 0.7;
      return RulerFace(p.x() - h.box->lo.x(),
                       (p.z() - h.box->lo.z()) / (h.box->hi.z() - h.box->lo.z()));
    case Mat::kPicture:
      return h.n.z() > 0.5 ? PictureFace(*h.box, p, room.seed) : Eigen::Vector3d{0.05, 0.04, 0.03};
    case Mat::kTableTop: {
      RoomPalette top = pal;
      top.plank_width_m = 0.25;
      return h.n.y() > 0.5 ? WoodPlanks(top, p.x(), p.z(), room.seed + 4) : pal.wood * 0.6;
    }
    case Mat::kPlain:
      break;
  }
  // Faces of books and boxes: the sides a little darker than the fronts (printing, wear).
  const double face = std::abs(h.n.z()) > 0.5 ? 1.0 : 0.85;
  return h.albedo * face * (0.95 + 0.1 * ValueNoise(p.x() * 200, p.y() * 200, room.seed + 9));
}

/// Ambient occlusion: darker near the junctions of walls and floor and under shelves.
double Occlusion(const Room& room, const Hit& h) {
  const auto near = [](double d, double depth, double scale) {
    return 1 - depth * std::exp(-std::max(0.0, d) / scale);
  };
  double ao = 1;
  const Eigen::Vector3d& p = h.p;
  if (h.n.y() > 0.5) {  // floor, table top and the tops of things
    ao *= near(p.z() - room.wall_z, 0.45, 0.05);
    if (std::isfinite(room.left_x)) ao *= near(p.x() - room.left_x, 0.45, 0.05);
    for (const Box& b : room.boxes)
      if (b.lo.y() <= p.y() + 1e-9 && b.hi.y() > p.y() + 0.01) {
        const double dx = std::max({b.lo.x() - p.x(), p.x() - b.hi.x(), 0.0});
        const double dz = std::max({b.lo.z() - p.z(), p.z() - b.hi.z(), 0.0});
        ao *= near(std::hypot(dx, dz), 0.5, 0.03);
      }
    for (const Cylinder& c : room.cylinders)
      if (std::abs(c.y0 - p.y()) < 1e-6)
        ao *= near(std::hypot(p.x() - c.x, p.z() - c.z) - c.radius, 0.5, 0.03);
  } else if (h.mat == Mat::kBackWall || h.mat == Mat::kSideWall) {
    ao *= near(p.y() - room.floor_y, 0.40, 0.05);
    if (h.mat == Mat::kBackWall && std::isfinite(room.left_x))
      ao *= near(p.x() - room.left_x, 0.4, 0.06);
    for (const Box* b : room.shelves)
      if (p.x() > b->lo.x() && p.x() < b->hi.x() && p.y() < b->lo.y())
        ao *= near(b->lo.y() - p.y(), 0.35, 0.04);
  }
  return ao;
}

/// The colour of one ray, and its share of direct light on the contact surface.
void ShadeRay(const Room& room, const RoomLight& light, const Eigen::Vector3d& o,
              const Eigen::Vector3d& d, const cv::Point& px, Eigen::Vector3d& colour,
              Eigen::Vector3d& direct) {
  Hit h = HitShell(room, o, d);
  for (std::size_t i = 0; i < room.boxes.size(); ++i)
    if (room.box_rects[i].contains(px)) HitBox(room.boxes[i], o, d, h);
  for (std::size_t i = 0; i < room.cylinders.size(); ++i)
    if (room.cylinder_rects[i].contains(px)) HitCylinder(room.cylinders[i], o, d, h);
  if (!std::isfinite(h.t)) {
    colour = Eigen::Vector3d::Constant(0.3) * light.Ambient();
    direct.setZero();
    return;
  }
  const Eigen::Vector3d albedo = Albedo(room, h);
  const Eigen::Vector3d lit = albedo * light.Direct(h.p, h.n);
  colour = albedo * light.Ambient(Occlusion(room, h)) + lit;
  const bool contact = h.n.y() > 0.5 && std::abs(h.p.y()) < 0.003 &&
                       (h.mat == Mat::kFloor || h.mat == Mat::kTableTop || h.mat == Mat::kRuler);
  direct = contact ? lit : Eigen::Vector3d::Zero();
}

}  // namespace

RoomLight::RoomLight(const RoomOptions& room, const Eigen::Vector3d& reference_W)
    : p_W_(room.light_p_W_m), radius_(room.light_radius_m) {
  ambient_ = room.ambient * room.brightness;
  const Eigen::Vector3d to = p_W_ - reference_W;
  const double cos_ref = std::max(0.05, to.normalized().y());
  direct_scale_ = (1 - room.ambient) * room.brightness * to.squaredNorm() / cos_ref;
}

double RoomLight::Direct(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const {
  const Eigen::Vector3d to = p_W_ - p;
  const double d2 = to.squaredNorm();
  return direct_scale_ * std::max(0.0, n.dot(to) / std::sqrt(d2)) / d2;
}

RoomImage RenderRoom(const FootageSpec& spec, const PinholeCamera& camera, const RoomLight& light,
                     int jobs) {
  const Room room = BuildRoom(spec, camera);
  const int w = camera.width_px(), h = camera.height_px();
  RoomImage out;
  out.linear.create(h, w, CV_32FC3);
  out.direct.create(h, w, CV_32FC3);
  const Eigen::Vector3d o = camera.p_W_m();
  core::ParallelFor(static_cast<std::size_t>(h), jobs, [&](std::size_t row) {
    const int y = static_cast<int>(row);
    auto* lin = out.linear.ptr<cv::Vec3f>(y);
    auto* dir = out.direct.ptr<cv::Vec3f>(y);
    for (int x = 0; x < w; ++x) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum_direct = Eigen::Vector3d::Zero();
      for (int s = 0; s < 4; ++s) {  // 2 x 2 rays a pixel
        Eigen::Vector3d c, d;
        ShadeRay(room, light, o, camera.RayW(x - 0.25 + 0.5 * (s & 1), y - 0.25 + 0.5 * (s >> 1)),
                 {x, y}, c, d);
        sum += c;
        sum_direct += d;
      }
      // Linear RGB in, BGR out (OpenCV's order).
      lin[x] = cv::Vec3f(static_cast<float>(sum.z() / 4), static_cast<float>(sum.y() / 4),
                         static_cast<float>(sum.x() / 4));
      dir[x] =
          cv::Vec3f(static_cast<float>(sum_direct.z() / 4), static_cast<float>(sum_direct.y() / 4),
                    static_cast<float>(sum_direct.x() / 4));
    }
  });
  return out;
}

double ShadowFraction(const Eigen::Vector3d& p, const Eigen::Vector3d& light, double light_radius,
                      const Eigen::Vector3d& c, double r) {
  const Eigen::Vector3d to_l = light - p, to_c = c - p;
  const double dl = to_l.norm(), dc = to_c.norm();
  if (dc <= r || to_c.dot(to_l) <= 0) return 0.0;
  const double a = std::asin(std::min(1.0, r / dc));  // the ball's angular radius
  const double theta = std::acos(std::clamp(to_l.dot(to_c) / (dl * dc), -1.0, 1.0));
  const double b = std::asin(std::min(1.0, light_radius / dl));
  if (b < 1e-9) return theta < a ? 1.0 : 0.0;  // a point light: a hard shadow
  if (theta >= a + b) return 0.0;
  if (theta <= a - b) return 1.0;
  if (theta <= b - a) return a * a / (b * b);
  // Area of the lens where two discs (radii a, b, centres theta apart) overlap.
  const double ca = std::clamp((theta * theta + a * a - b * b) / (2 * theta * a), -1.0, 1.0);
  const double cb = std::clamp((theta * theta + b * b - a * a) / (2 * theta * b), -1.0, 1.0);
  const double lens = a * a * std::acos(ca) + b * b * std::acos(cb) -
                      0.5 * std::sqrt(std::max(0.0, (-theta + a + b) * (theta + a - b) *
                                                        (theta - a + b) * (theta + a + b)));
  return std::clamp(lens / (std::numbers::pi * b * b), 0.0, 1.0);
}

}  // namespace hoof::synth
