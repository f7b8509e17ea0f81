"""The report: its document model (Markdown and PDF), figures, text, and the build.

May import every package but ``grading`` and the CLI.
"""
