#!/usr/bin/python3
"""What glTF's dielectric specular layer would change in a lightmap (issue 37, docs/gltf.md).

glTF's metallic-roughness BRDF for a non-metal (glTF 2.0, Appendix B) is
    f = (1 - F) base/pi + F D V,   F = 0.04 + 0.96 (1 - |v.h|)^5,
D GGX and V the separable Smith visibility, alpha = roughness^2. lightbake reads every
non-metal as Lambert (f = base/pi). A lightmap holds irradiance, which no view-dependent lobe
enters; what the layer changes for baked light is how much each surface sends on, its albedo.
This prints the layer's albedo, averaged over cosine-weighted incidence (a diffuse field's),
against Lambert's, by quadrature (Gauss-Legendre in cos theta, midpoints in phi).

    /usr/bin/python3 bench/gltf_dielectric_albedo.py
"""

import numpy as np


def mean_albedo(base, roughness, layer=True, n=200):
    """Cosine-weighted mean over incidence of the BRDF's directional albedo."""
    a2 = roughness ** 4
    x, w = np.polynomial.legendre.leggauss(n)
    mu, w_mu = 0.5 * (x + 1.0), 0.5 * w  # cos theta in (0, 1)
    phi = (np.arange(2 * n) + 0.5) * np.pi / (2 * n)  # [0, pi]; the other half mirrors it
    w_phi = 2.0 * np.pi / (2 * n)
    out_mu, out_phi = np.meshgrid(mu, phi, indexing="ij")
    sin_out = np.sqrt(1.0 - out_mu ** 2)
    out = np.stack([sin_out * np.cos(out_phi), sin_out * np.sin(out_phi), out_mu], -1)

    def g1(c):
        return 2.0 * c / (c + np.sqrt(a2 + (1.0 - a2) * c * c))

    total = 0.0
    for mu_in, weight in zip(mu, w_mu):
        into = np.array([np.sqrt(1.0 - mu_in ** 2), 0.0, mu_in])
        h = out + into
        h /= np.linalg.norm(h, axis=-1, keepdims=True)
        fresnel = 0.04 + 0.96 * (1.0 - np.clip(h @ into, 0.0, 1.0)) ** 5 if layer else 0.0
        ggx = a2 / (np.pi * (h[..., 2] ** 2 * (a2 - 1.0) + 1.0) ** 2)
        visibility = g1(out_mu) * g1(mu_in) / (4.0 * out_mu * mu_in)
        brdf = (1.0 - fresnel) * base / np.pi + fresnel * ggx * visibility
        albedo = (brdf * out_mu * w_mu[:, None] * w_phi).sum()
        total += albedo * 2.0 * mu_in * weight
    return total


def main():
    lambert = mean_albedo(0.5, 1.0, layer=False)
    assert abs(lambert - 0.5) < 1e-6, lambert  # the quadrature integrates Lambert exactly
    print("| roughness | base 0.2 | base 0.5 | base 0.8 |")
    print("|---|---|---|---|")
    for roughness in (1.0, 0.5):
        cells = [f"{mean_albedo(base, roughness) / base:.3f}" for base in (0.2, 0.5, 0.8)]
        print(f"| {roughness} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
