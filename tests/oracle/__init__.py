"""Independent plain NumPy + SciPy oracle for the rattleback equations (no celtstone imports)."""
