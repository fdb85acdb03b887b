// eye.geo: the keratome parametric eye for the gmsh GUI (gmsh 4.8, OpenCASCADE kernel).
//
// This script mirrors what lib/model/eye.c builds through the gmsh C API (see meshes/README.md):
// the rotationally symmetric base eye, one incision-ready ring, the same physical groups and
// the same size fields. Two things only lib/model/eye.c does: the toric anterior surface (the
// mesh nodes are mapped onto it after meshing, see README) and the general placement rules
// (limbal rings, validation, several rings). The default values are those of plans/eye.yaml;
// change them in the GUI (Eye/...) or with `gmsh -setnumber name value`.
//
//   gmsh meshes/eye.geo                      # look at the geometry, mesh interactively
//   gmsh -3 meshes/eye.geo -o /tmp/eye.msh   # batch mesh (base eye, P1)

SetFactory("OpenCASCADE");

DefineConstant[
  r_steep = {7.667, Name "Eye/01 anterior radius, steep meridian (mm)"},
  r_flat = {7.938, Name "Eye/02 anterior radius, flat meridian (mm)"},
  r_post = {6.7, Name "Eye/03 posterior apical radius (mm)"},
  t_c = {0.54, Name "Eye/04 central thickness (mm)"},
  t_p = {0.67, Name "Eye/05 peripheral thickness (mm)"},
  wtw = {11.7, Name "Eye/06 white-to-white diameter (mm)"},
  lw = {1.0, Name "Eye/07 limbus width (mm)"},
  sclera = {0.53, Name "Eye/08 sclera thickness (mm)"},
  Rg = {12, Name "Eye/09 globe radius (mm)"},
  extent = {90, Name "Eye/10 extent, polar angle (deg, < 180 here)"},
  oz = {7, Name "Eye/11 optical zone diameter (mm)"},
  ring_d = {10.5, Name "Eye/12 ring diameter (mm)"},
  ring_f = {0.9, Name "Eye/13 ring depth fraction"},
  h_opt = {0.25, Name "Mesh sizes/optical zone (mm)"},
  h_inc = {0.15, Name "Mesh sizes/incision (mm)"},
  h_cor = {0.4, Name "Mesh sizes/cornea (mm)"},
  h_scl = {1.2, Name "Mesh sizes/sclera (mm)"}
];

// ---- derived geometry (same formulas as lib/model/eye_geom.c) --------------------------------
Ra = 2 / (1 / r_steep + 1 / r_flat);       // mean anterior radius (mean curvature)
rc = wtw / 2;  rL = rc + lw;  Ri = Rg - sclera;
zE = Sqrt(Rg^2 - rc^2);                    // corneal edge E on the outer globe sphere
zCa = zE - Sqrt(Ra^2 - rc^2);              // anterior sphere centre
zA = zCa + Ra;                             // apex
phic = Asin(rc / Ra);
PpX = rc - t_p * Sin(phic);  PpZ = zE - t_p * Cos(phic);  // t_p along the normal at E
zPv = zA - t_c;                            // posterior vertex
sp = zPv - PpZ;
k = (2 * r_post * sp - PpX^2) / sp^2;      // 1 + Q of the posterior ellipse through Pp
ea = r_post / k;  eb = r_post / Sqrt(k);  zEc = zPv - ea;
aL = Asin(rL / Rg);  aX = extent * Pi / 180;
// both interfaces of the limbus: the corneal normal at E and the globe radius at aL
hc = h_cor;  If (t_c / 2.5 < hc) hc = t_c / 2.5; EndIf   // >= 2 elements through the cornea
ho = h_opt;  If (t_c / 2.5 < ho) ho = t_c / 2.5; EndIf

// ---- profile in the x-z half-plane (x = distance from the axis) ------------------------
Point(1) = {0, 0, zA};                     // apex
Point(2) = {0, 0, zCa};                    // anterior centre (construction)
Point(3) = {0, 0, 0};                      // globe centre (construction)
Point(4) = {0, 0, zPv};
Point(5) = {rc, 0, zE};                    // E
Point(6) = {PpX, 0, PpZ};                  // Pp
Point(7) = {Rg * Sin(aL), 0, Rg * Cos(aL)};  // Lo
Point(8) = {Ri * Sin(aL), 0, Ri * Cos(aL)};  // Li
Point(9) = {Rg * Sin(aX), 0, Rg * Cos(aX)};  // So
Point(10) = {Ri * Sin(aX), 0, Ri * Cos(aX)}; // Si
Point(11) = {0, 0, zEc};                   // ellipse centre (construction)
Circle(1) = {1, 2, 5};                     // anterior cornea (mean sphere)
Line(2) = {5, 6};                          // cornea | limbus
If (k < 1)
  Ellipse(3) = {4, 11, 4, 6};              // prolate: major axis along z
Else
  Point(12) = {eb, 0, zEc};
  Ellipse(3) = {4, 11, 12, 6};             // oblate: major axis radial
EndIf
Line(4) = {4, 1};                          // axis
Circle(5) = {5, 3, 7};                     // limbus outer
Line(6) = {7, 8};                          // limbus | sclera
Line(7) = {8, 6};                          // limbus inner
Circle(8) = {7, 3, 9};                     // sclera outer
Line(9) = {9, 10};                         // rim
Circle(10) = {10, 3, 8};                   // sclera inner
Curve Loop(1) = {1, 2, 3, 4};   Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 2};   Plane Surface(2) = {2};
Curve Loop(3) = {8, 9, 10, 6};  Plane Surface(3) = {3};

// ---- incision ring: along the corneal normal, from 0.1 mm outside to its depth ---------
rr = ring_d / 2;  phr = Asin(rr / Ra);  s = Sin(phr);  c = Cos(phr);
D = zPv - zCa;  qa = s^2 + k * c^2;  qb = 2 * c * (r_post - k * D);  qc = k * D^2 - 2 * r_post * D;
tr = Ra - (-qb + Sqrt(qb^2 - 4 * qa * qc)) / (2 * qa);   // local thickness along the normal
depth = ring_f * tr;
zTop = zCa + Ra * c;
Point(20) = {rr + 0.1 * s, 0, zTop + 0.1 * c};
Point(21) = {rr - depth * s, 0, zTop - depth * c};
Line(20) = {20, 21};

vc[] = Extrude {{0, 0, 1}, {0, 0, 0}, 2 * Pi} { Surface{1}; };
vl[] = Extrude {{0, 0, 1}, {0, 0, 0}, 2 * Pi} { Surface{2}; };
vs[] = Extrude {{0, 0, 1}, {0, 0, 0}, 2 * Pi} { Surface{3}; };
rs[] = Extrude {{0, 0, 1}, {0, 0, 0}, 2 * Pi} { Curve{20}; };
Recursive Delete { Surface{1, 2, 3}; Curve{20}; }
Delete { Point{2, 3, 11}; }
BooleanFragments { Volume{vc[1], vl[1], vs[1]}; Delete; }{ Surface{rs[1]}; Delete; }
e = 1e-6;
// the stub outside the eye
Recursive Delete { Surface{ Surface In BoundingBox{-rr - 1, -rr - 1, zTop - e, rr + 1, rr + 1, zTop + 0.2} }; }

// ---- physical groups (names and tags of lib/model/eye.h) --------------------------------------
Physical Volume("cornea", 1) = Volume In BoundingBox{-rc - e, -rc - e, PpZ - e, rc + e, rc + e, zA + e};
Physical Volume("limbus", 2) = Volume In BoundingBox{-rL - e, -rL - e, Ri * Cos(aL) - e, rL + e, rL + e, zE + e};
zlo = Min(Rg * Cos(aX), Ri * Cos(aX));  zhi = Max(Rg * Cos(aX), Ri * Cos(aX));  // the rim
Physical Volume("sclera", 3) = Volume In BoundingBox{-Rg - e, -Rg - e, zlo - e, Rg + e, Rg + e, Rg * Cos(aL) + e};
zBot = zTop - depth * c;
ring[] = Surface In BoundingBox{-rr - e, -rr - e, zBot - e, rr + e, rr + e, zTop + e};
ant[] = Surface In BoundingBox{-rc - e, -rc - e, zE - e, rc + e, rc + e, zA + e};
ant[] -= ring[];
post[] = Surface In BoundingBox{-PpX - e, -PpX - e, PpZ - e, PpX + e, PpX + e, zPv + e};
post[] -= ring[];
limin[] = Surface In BoundingBox{-Ri * Sin(aL) - e, -Ri * Sin(aL) - e, Ri * Cos(aL) - e, Ri * Sin(aL) + e, Ri * Sin(aL) + e, PpZ + e};
xi = Ri;  If (aX < Pi / 2) xi = Ri * Sin(aX); EndIf   // keeps the rim out of the box
sclin[] = Surface In BoundingBox{-xi - e, -xi - e, Ri * Cos(aX) - e, xi + e, xi + e, Ri * Cos(aL) + e};
limout[] = Surface In BoundingBox{-Rg * Sin(aL) - e, -Rg * Sin(aL) - e, Rg * Cos(aL) - e, Rg * Sin(aL) + e, Rg * Sin(aL) + e, zE + e};
limout[] -= Surface In BoundingBox{-rc - e, -rc - e, PpZ - e, rc + e, rc + e, zE + e}; // cornea|limbus
sclout[] = Surface In BoundingBox{-Rg - e, -Rg - e, Rg * Cos(aX) - e, Rg + e, Rg + e, Rg * Cos(aL) + e};
sclout[] -= sclin[];
sclout[] -= Surface In BoundingBox{-Rg - e, -Rg - e, Ri * Cos(aL) - e, Rg * Sin(aL) + e, Rg * Sin(aL) + e, Rg * Cos(aL) + e}; // limbus|sclera
em = sclera / 2;  // OpenCASCADE's boxes of cones are not tight
rim[] = Surface In BoundingBox{-Rg - em, -Rg - em, zlo - em, Rg + em, Rg + em, zhi + em};
rim[] -= sclin[];
sclout[] -= rim[];
Physical Surface("anterior", 1) = {ant[]};
Physical Surface("inner", 2) = {post[], limin[], sclin[]};
Physical Surface("fixed", 3) = {rim[]};
Physical Surface("outer", 4) = {limout[], sclout[]};
Physical Surface("incision-ring-1", 11) = {ring[]};

// ---- size fields (as in lib/model/eye.c) ----------------------------------------------------
hmax = h_scl;  If (hc > hmax) hmax = hc; EndIf
Field[1] = MathEval;   // distance from the axis, switched off below the corneal edge
Field[1].F = Sprintf("sqrt(x*x+y*y) + 100*((%.17g - z) + Fabs(%.17g - z))", PpZ, PpZ);
If (ho < hc)           // grade from ho to hc over 2 hc, then on to hmax
  Field[2] = Threshold;
  Field[2].InField = 1;  Field[2].SizeMin = ho;  Field[2].SizeMax = hmax;
  Field[2].DistMin = oz / 2;  Field[2].DistMax = oz / 2 + 2 * hc * (hmax - ho) / (hc - ho);
Else                   // nothing to refine (ho capped to hc)
  Field[2] = MathEval;  Field[2].F = Sprintf("%.17g", hmax);
EndIf
Field[3] = MathEval;   // polar angle about the globe centre
Field[3].F = "acos(z/sqrt(x*x+y*y+z*z+1e-12))";
Field[4] = Threshold;
Field[4].InField = 3;  Field[4].SizeMin = hc;  Field[4].SizeMax = h_scl;
Field[4].DistMin = aL;  Field[4].DistMax = aL + 3 * h_scl / Rg;
Field[5] = Distance;   // the ring faces, sampled at about a fifth of h_inc
Field[5].SurfacesList = {ring[]};
Field[5].NumPointsPerCurve = Ceil(6 * rL / h_inc);
If (h_inc < hc)
  Field[6] = Threshold;
  Field[6].InField = 5;  Field[6].SizeMin = h_inc;  Field[6].SizeMax = hmax;
  Field[6].DistMin = h_inc / 2;  Field[6].DistMax = h_inc / 2 + 2 * hc * (hmax - h_inc) / (hc - h_inc);
Else
  Field[6] = MathEval;  Field[6].F = Sprintf("%.17g", hmax);
EndIf
Field[7] = Min;
Field[7].FieldsList = {2, 4, 6};
Background Field = 7;

Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeMax = hmax;
Mesh.Algorithm3D = 10;
